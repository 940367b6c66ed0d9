#!/usr/bin/env python3
"""How much of a shape's size one view shows, and what knowing the rest would buy.

For the held-out views of a `lista-sim views` folder (docs/datasets.md) this
measures each view's footprint sides and height in the views' own object frame
(the shape's axes: an oracle yaw no descriptor gets) and scores top-1 instance
retrieval by nearest neighbour on the logs of (shorter side, longer side,
height), as the benchmark scores descriptors: once as measured, then with the
true height, the true footprint, or both put in from index.json's
`shapes[].extent`. The gap between "measured" and "true footprint" is what a
view's unseen depth costs. Pure Python (no numpy): a minute per 1000 views.

    python3 bench/scripts/extent_oracle.py /tmp/single-41
"""
import json
import math
import statistics
import struct
import sys


def read_xyz(path):
    """Points of a binary PCD whose first three fields are float32 x y z."""
    data = open(path, 'rb').read()
    start = data.index(b'DATA binary\n') + len(b'DATA binary\n')
    header = data[:start].decode().split('\n')
    field = lambda key: next(l for l in header if l.startswith(key + ' ')).split()[1:]
    sizes = [int(s) for s in field('SIZE')]
    count = int(field('POINTS')[0])
    stride = sum(sizes)
    return [struct.unpack_from('<3f', data, start + k * stride) for k in range(count)]


def log_sizes(short_side, long_side, height):
    return [math.log(max(v, 0.01)) for v in (short_side, long_side, height)]


def top1(features, labels):
    hits = 0
    for i, f in enumerate(features):
        nearest = min((j for j in range(len(features)) if j != i),
                      key=lambda j: sum((a - b) ** 2 for a, b in zip(f, features[j])))
        hits += labels[nearest] == labels[i]
    return hits / len(features)


def main(folder):
    try:
        index = json.load(open(folder + '/index.json'))
    except (OSError, ValueError) as e:
        sys.exit(f'extent_oracle.py: cannot read {folder}/index.json ({e}); give a lista-sim views folder')
    if index.get('format') != 'lista-views/1':
        sys.exit(f'extent_oracle.py: {folder}/index.json is not "lista-views/1"; give a lista-sim views folder')
    extent = {s['id']: s['extent'] for s in index['shapes']}
    views = [v for v in index['views'] if v.get('split', 'train') != 'train']
    measured, true, labels, sensors = [], [], [], []
    for v in views:
        try:
            pts = read_xyz(folder + '/' + v['file'])
        except (OSError, ValueError, struct.error) as e:
            sys.exit(f"extent_oracle.py: cannot read {folder}/{v['file']} ({e}): a binary PCD with x y z first")
        dx = max(p[0] for p in pts) - min(p[0] for p in pts)
        dy = max(p[1] for p in pts) - min(p[1] for p in pts)
        measured.append((sorted((dx, dy)), max(p[2] for p in pts)))  # views stand on z = 0
        e = extent[v['shape']]
        true.append((sorted(e[:2]), e[2]))
        labels.append(v['shape'])
        sensors.append(v.get('sensor', '?'))
    print(f'{folder}: {len(views)} held-out views of {len(set(labels))} shapes')
    for name, footprint_true, height_true in (('measured', 0, 0), ('true height', 0, 1),
                                              ('true footprint', 1, 0), ('true both', 1, 1)):
        feats = [log_sizes(*(t if footprint_true else m)[0], (t if height_true else m)[1])
                 for m, t in zip(measured, true)]
        print(f'  top-1, nearest neighbour on log sizes, {name:15s} {top1(feats, labels):.3f}')
    shown = [m[0][0] / max(t[0][0], 1e-3) for m, t in zip(measured, true)]
    print(f'  shorter footprint side shown: median {statistics.median(shown):.2f}, '
          f'lowest tenth under {sorted(shown)[len(shown) // 10]:.2f} of the truth')
    for s in sorted(set(sensors)):
        short = [t[1] - m[1] for m, t, x in zip(measured, true, sensors) if x == s]
        print(f'  {s}: height under-read median {statistics.median(short) * 100:.1f} cm, '
              f'90th percentile {sorted(short)[int(0.9 * len(short))] * 100:.1f} cm')


if __name__ == '__main__':
    if len(sys.argv) != 2:
        sys.exit('usage: extent_oracle.py <lista-sim views folder>')
    main(sys.argv[1])
