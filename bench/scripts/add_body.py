#!/usr/bin/env python3
# Copies a lista-sim dataset (binary PCD scans with x y z intensity label)
# and adds a robot body, points that move with the sensor, to every scan: a
# 1.1 x 0.5 m box whose top lies 0.15 m under the sensor, its sides down to
# 0.45 m, as a LiDAR on a legged robot's back sees it; label 0. Used by
# docs/bench/end-to-end.md to measure io.missions' min_range.
#   add_body.py SRC_DATASET DST_DATASET
import sys, os, shutil, struct, random
src, dst = sys.argv[1], sys.argv[2]
shutil.rmtree(dst, ignore_errors=True)
shutil.copytree(src, dst)
rng = random.Random(5)
def body_points(n=600):
    pts = []
    for _ in range(n):
        face = rng.random()
        if face < 0.6:   # top
            pts.append((rng.uniform(-0.9, 0.2), rng.uniform(-0.25, 0.25), -0.15))
        elif face < 0.8: # left/right sides
            pts.append((rng.uniform(-0.9, 0.2), rng.choice([-0.25, 0.25]), rng.uniform(-0.45, -0.15)))
        else:            # front/back
            pts.append((rng.choice([-0.9, 0.2]), rng.uniform(-0.25, 0.25), rng.uniform(-0.45, -0.15)))
    return pts
for m in os.listdir(dst):
    d = os.path.join(dst, m, 'scans')
    if not os.path.isdir(d): continue
    for f in sorted(os.listdir(d)):
        p = os.path.join(d, f)
        data = open(p, 'rb').read()
        i = data.index(b'DATA binary\n') + len(b'DATA binary\n')
        header = data[:i].decode().splitlines()
        body = data[i:]
        n = int([l for l in header if l.startswith('POINTS')][0].split()[1])
        assert len(body) == n * 20, (p, len(body), n)
        extra = b''.join(struct.pack('<ffffI', x, y, z, 0.2, 0) for x, y, z in body_points())
        m2 = n + len(extra) // 20
        header = [('WIDTH %d' % m2) if l.startswith('WIDTH') else ('POINTS %d' % m2) if l.startswith('POINTS') else l for l in header]
        open(p, 'wb').write(('\n'.join(header) + '\n').encode() + body + extra)
