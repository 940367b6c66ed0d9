#!/usr/bin/env python3
"""A copy of a dataset with one mission's map frame tilted off gravity.

    tilt_map.py SRC DST MISSION ROLL_DEG PITCH_DEG

MISSION's poses.txt (TUM or KITTI) become R * T, R = roll about x then pitch
about y, as if its SLAM run had started on a slope; ground_truth.json's
mission_to_world, if there is one, follows (M * R^-1), so the truth is
unchanged. The other missions' poses and every scan stay as they were
(scans/ linked, not copied). For any dataset, real ones included: does a
run stay level? (docs/bench/alignment.md, 2026-12-02). lista-sim
--map-tilt makes such sets from scratch.
"""
import json
import math
import os
import shutil
import sys


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(len(b))) for j in range(len(b[0]))] for i in range(len(a))]


def quat_to_matrix(x, y, z, w):
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def matrix_to_quat(m):
    t = m[0][0] + m[1][1] + m[2][2]
    if t > 0:
        s = 2 * math.sqrt(1 + t)
        return ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, s / 4)
    i = max(range(3), key=lambda k: m[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2 * math.sqrt(1 + m[i][i] - m[j][j] - m[k][k])
    q = [0.0, 0.0, 0.0, (m[k][j] - m[j][k]) / s]
    q[i], q[j], q[k] = s / 4, (m[j][i] + m[i][j]) / s, (m[k][i] + m[i][k]) / s
    return tuple(q)


def tilt_matrix(roll_deg, pitch_deg):
    r, p = math.radians(roll_deg), math.radians(pitch_deg)
    rx = [[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]]
    ry = [[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]]
    return matmul(rx, ry)


def tilted_line(line, rot, where):
    f = line.split('#')[0].split()
    if not f:
        return line.rstrip('\n')
    if len(f) == 8:  # TUM: t x y z qx qy qz qw
        t = matmul(rot, [[float(v)] for v in f[1:4]])
        m = matmul(rot, quat_to_matrix(*map(float, f[4:8])))
        return ' '.join([f[0]] + ['%.17g' % v[0] for v in t] + ['%.17g' % v for v in matrix_to_quat(m)])
    if len(f) == 12:  # KITTI: [R|t] row-major
        v = list(map(float, f))
        rt = matmul(rot, [v[0:4], v[4:8], v[8:12]])
        return ' '.join('%.17g' % x for row in rt for x in row)
    sys.exit(f'tilt_map.py: {where}: {len(f)} fields, neither TUM (8) nor KITTI (12)')


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    src, dst, mission = sys.argv[1], sys.argv[2], sys.argv[3]
    rot = tilt_matrix(float(sys.argv[4]), float(sys.argv[5]))
    if not os.path.isfile(os.path.join(src, mission, 'poses.txt')):
        sys.exit(f'tilt_map.py: {src}/{mission}/poses.txt not found: name a mission of the dataset')
    if os.path.exists(dst):
        sys.exit(f'tilt_map.py: {dst} exists; give a new folder')
    os.makedirs(dst)
    for m in sorted(os.listdir(src)):
        sp = os.path.join(src, m)
        if not os.path.isfile(os.path.join(sp, 'poses.txt')):
            continue
        os.makedirs(os.path.join(dst, m))
        os.symlink(os.path.abspath(os.path.join(sp, 'scans')), os.path.join(dst, m, 'scans'))
        if os.path.isfile(os.path.join(sp, 'poses_gt.txt')):
            shutil.copy(os.path.join(sp, 'poses_gt.txt'), os.path.join(dst, m))
        path = os.path.join(sp, 'poses.txt')
        lines = [tilted_line(l, rot, f'{path}:{n + 1}') if m == mission else l.rstrip('\n')
                 for n, l in enumerate(open(path))]
        with open(os.path.join(dst, m, 'poses.txt'), 'w') as out:
            out.write('\n'.join(lines) + '\n')
    truth = os.path.join(src, 'ground_truth.json')
    if os.path.isfile(truth):
        g = json.load(open(truth))
        mw = g['mission_to_world'][mission]
        inverse = [list(r) for r in zip(*rot)]  # R^-1 = R^T
        top = matmul([row[:3] for row in mw[:3]], inverse)
        g['mission_to_world'][mission] = [top[i] + [mw[i][3]] for i in range(3)] + [mw[3]]
        with open(os.path.join(dst, 'ground_truth.json'), 'w') as out:
            json.dump(g, out)


if __name__ == '__main__':
    main()
