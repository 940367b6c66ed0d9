#!/usr/bin/env python3
"""Bends one mission of a LiSTA dataset as a SLAM map drifts: every point
whose world x (at the poses of poses_gt.txt) is past X0 is moved by D,
ramped in over RAMP metres. Scans are rewritten in place (binary PCD).
usage: bench/volumetric/bend_mission.py MISSION_DIR X0 RAMP DX DY DZ
(docs/bench/end-to-end.md, "A map bent in one region")."""
import os, struct, sys

if len(sys.argv) != 7:
    sys.exit(__doc__.strip().splitlines()[-2])
mission, x0, ramp, dx, dy, dz = sys.argv[1], *map(float, sys.argv[2:7])
poses = [list(map(float, l.split())) for l in open(os.path.join(mission, "poses_gt.txt")) if l.strip()]
scans = sorted(f for f in os.listdir(os.path.join(mission, "scans")) if f.endswith(".pcd"))
assert len(scans) == len(poses), (len(scans), len(poses))

def matrix(qx, qy, qz, qw):
    return [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
            [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
            [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]

moved = total = 0
for name, pose in zip(scans, poses):
    path = os.path.join(mission, "scans", name)
    data = open(path, "rb").read()
    end = data.index(b"DATA binary\n") + len(b"DATA binary\n")
    header = data[:end].decode()
    fields = dict(l.split(" ", 1) for l in header.splitlines() if " " in l and not l.startswith("#"))
    sizes = list(map(int, fields["SIZE"].split()))
    counts = list(map(int, fields["COUNT"].split()))
    names = fields["FIELDS"].split()
    assert names[:3] == ["x", "y", "z"] and sizes[:3] == [4, 4, 4]
    stride = sum(s * c for s, c in zip(sizes, counts))
    n = int(fields["POINTS"])
    body = bytearray(data[end:end + n * stride])
    t = pose[1:4]
    r = matrix(*pose[4:8])
    for i in range(n):
        o = i * stride
        px, py, pz = struct.unpack_from("<fff", body, o)
        w = [r[k][0] * px + r[k][1] * py + r[k][2] * pz + t[k] for k in range(3)]
        total += 1
        if w[0] <= x0:
            continue
        a = min(1.0, (w[0] - x0) / ramp) if ramp > 0 else 1.0
        w = [w[0] + a * dx - t[0], w[1] + a * dy - t[1], w[2] + a * dz - t[2]]
        s = [r[0][k] * w[0] + r[1][k] * w[1] + r[2][k] * w[2] for k in range(3)]
        struct.pack_into("<fff", body, o, *s)
        moved += 1
    open(path, "wb").write(data[:end] + bytes(body) + data[end + n * stride:])
print(f"{moved} of {total} points moved", file=sys.stderr)
