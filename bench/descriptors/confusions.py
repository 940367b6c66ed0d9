import json, numpy as np, sys, collections
j=json.load(open('/tmp/desc-views/index.json'))
shape={s['id']:s for s in j['shapes']}
labels={}; 
for v in j['views']: labels.setdefault(v['shape'], len(labels))
inv={l:s for s,l in labels.items()}
d=np.loadtxt(sys.argv[1],delimiter=',',skiprows=1)
lab=d[:,0].astype(int); X=d[:,2:]
D=((X[:,None,:]-X[None,:,:])**2).sum(-1); np.fill_diagonal(D,1e9)
nn=D.argmin(1)
wrong=lab[nn]!=lab
print("top1",1-wrong.mean())
same_cls=0; ext=[]
pairs=collections.Counter()
for i in np.where(wrong)[0]:
  a=shape[inv[lab[i]]]; b=shape[inv[lab[nn[i]]]]
  if a['class']==b['class']: same_cls+=1
  ext.append(np.abs(np.array(a['extent'])-np.array(b['extent'])).max())
  pairs[(a['class'],b['class'])]+=1
ext=np.array(ext)
print("wrong",wrong.sum(),"same class",same_cls, "max extent diff p25/50/75", np.percentile(ext,[25,50,75]))
print(pairs.most_common(12))
cls=collections.Counter(shape[inv[l]]['class'] for l in set(lab))
print("held-out shapes per class",cls)
