#!/usr/bin/env python3
"""Which true changes a run misses, and where they were lost.

  bench/segmentation/missed.py DATASET RUN [RUN...]

For every truly changed object (data contract, section 3: added, removed or
moved between consecutive missions) and every mission it has points in, prints
its point count and, per run folder (report.json + changes/), the share of its
points reported changed and the best IoU of one reported object with it (the
object-level pairing needs > 0.5). Giving the runs of an ablation (e.g.
/tmp/lista-seg-ablate/exp1/{volumetric,no_morphology,no_ground,full}) shows
which stage lost which object. Ends with a summary per kind of change.
Plain Python 3 (no numpy): reads binary/ascii PCD scans, not compressed ones.
"""
import json, math, os, struct, sys
from collections import defaultdict


def read_pcd(path, want):
    with open(path, "rb") as f:
        head = {}
        while True:
            line = f.readline().decode("ascii", "replace").strip()
            if not line or line.startswith("#"):
                continue
            k, *v = line.split()
            head[k] = v
            if k == "DATA":
                break
        names, sizes, types = head["FIELDS"], [int(s) for s in head["SIZE"]], head["TYPE"]
        counts = [int(c) for c in head.get("COUNT", ["1"] * len(names))]
        n = int(head["POINTS"][0])
        mode = head["DATA"][0]
        if mode == "binary_compressed":
            sys.exit(f"missed.py: error: {path}: binary_compressed PCD is not supported here")
        cols = {}
        if mode == "ascii":
            rows = [l.split() for l in f.read().decode().splitlines() if l.strip()]
            for w in want:
                i = sum(counts[: names.index(w)])
                cols[w] = [float(r[i]) if types[names.index(w)] == "F" else int(r[i]) for r in rows]
            return cols
        stride = sum(s * c for s, c in zip(sizes, counts))
        data = f.read(n * stride)
        for w in want:
            j = names.index(w)
            off = sum(s * c for s, c in zip(sizes[:j], counts[:j]))
            code = {("F", 4): "f", ("U", 4): "I", ("I", 4): "i", ("U", 2): "H", ("U", 1): "B"}[(types[j], sizes[j])]
            cols[w] = [v[0] for v in struct.iter_unpack("<" + code, b"".join(
                data[k * stride + off:k * stride + off + sizes[j]] for k in range(n)))] if n else []
    return cols


def moved(a, b):
    t = math.dist([a[i][3] for i in range(3)], [b[i][3] for i in range(3)])
    tr = sum(sum(a[r][k] * b[r][k] for r in range(3)) for k in range(3))  # trace(Ra^T Rb)
    ang = math.degrees(math.acos(max(-1.0, min(1.0, (tr - 1) / 2))))
    return t > 0.05 or ang > 5.0


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    dataset, runs = sys.argv[1], sys.argv[2:]
    truth = json.load(open(os.path.join(dataset, "ground_truth.json")))
    missions = truth["missions"]
    kind = {}  # (object id, mission) -> kind
    for o in truth["objects"]:
        if o.get("dynamic"):
            continue
        for i, m in enumerate(missions):
            p = o["poses"].get(m)
            if p is None:
                continue
            for j in (i - 1, i + 1):
                if 0 <= j < len(missions):
                    q = o["poses"].get(missions[j])
                    k = ("added" if j < i else "removed") if q is None else ("moved" if moved(p, q) else None)
                    if k and (o["id"], m) not in kind:
                        kind[(o["id"], m)] = (k, o["class"])
    # Labels of every point, keyed by (scan, index).
    labels = {}
    size = defaultdict(int)
    for m in missions:
        scans = sorted(os.listdir(os.path.join(dataset, m, "scans")))
        lab = []
        for s, f in enumerate(scans):
            lab.append(read_pcd(os.path.join(dataset, m, "scans", f), ["label"])["label"])
            for l in lab[-1]:
                if (l, m) in kind:
                    size[(l, m)] += 1
        labels[m] = lab
    hits = []  # per run: (obj, mission) -> reported points; best IoU
    for r in runs:
        got, per_obj = defaultdict(int), defaultdict(lambda: defaultdict(int))
        obj_size = defaultdict(int)
        for m in missions:
            c = read_pcd(os.path.join(r, "changes", m + ".pcd"), ["scan", "index", "object"])
            for s, i, ob in zip(c["scan"], c["index"], c["object"]):
                l = labels[m][s][i]
                obj_size[(ob, m)] += 1
                if (l, m) in kind:
                    got[(l, m)] += 1
                    if ob >= 0:
                        per_obj[(l, m)][ob] += 1
        best = {}
        for key, byob in per_obj.items():
            best[key] = max(k / (obj_size[(ob, key[1])] + size[key] - k) for ob, k in byob.items())
        hits.append((got, best))
    names = [os.path.basename(r.rstrip("/")) for r in runs]
    print("| object | class | kind | mission | points | " + " | ".join(f"{n} share / IoU" for n in names) + " |")
    print("|---" * (5 + len(names)) + "|")
    summary = defaultdict(lambda: [0] + [0] * len(runs))
    for key in sorted(kind, key=lambda k: (kind[k][0], k)):
        k, cls = kind[key]
        n = size.get(key, 0)
        if n == 0:
            continue  # not seen in that mission
        cells = []
        summary[k][0] += 1
        for ri, (got, best) in enumerate(hits):
            iou = best.get(key, 0.0)
            summary[k][ri + 1] += iou > 0.5
            cells.append(f"{got.get(key, 0) / n:.2f} / {iou:.2f}")
        print(f"| {key[0]} | {cls} | {k} | {key[1]} | {n} | " + " | ".join(cells) + " |")
    print("\n| kind | object appearances | " + " | ".join(f"{n}: paired" for n in names) + " |")
    print("|---" * (2 + len(names)) + "|")
    for k, v in sorted(summary.items()):
        print(f"| {k} | {v[0]} | " + " | ".join(str(x) for x in v[1:]) + " |")


if __name__ == "__main__":
    main()
