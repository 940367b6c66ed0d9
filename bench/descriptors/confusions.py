#!/usr/bin/env python3
"""Which shapes a descriptor confuses: reads a lista-sim views folder and the
rows `lista-bench descriptors --rows DIR` wrote for one plugin, and prints
top-1, how many wrong nearest neighbours are of the same class, how far
their footprints/heights differ (largest extent difference, m) and the most
confused class pairs.

    bench/descriptors/confusions.py /tmp/desc-views /tmp/rows/describe.learned.csv
"""
import collections
import json
import sys

import numpy as np


def main(views_dir, rows_csv):
    index = json.load(open(f"{views_dir}/index.json"))
    shapes = {s["id"]: s for s in index["shapes"]}
    # Labels as lista's reader gives them: shapes numbered in order of first view.
    labels = {}
    for v in index["views"]:
        labels.setdefault(v["shape"], len(labels))
    shape_of = {label: shape for shape, label in labels.items()}
    data = np.loadtxt(rows_csv, delimiter=",", skiprows=1, ndmin=2)
    label, rows = data[:, 0].astype(int), data[:, 2:]
    dist = ((rows[:, None, :] - rows[None, :, :]) ** 2).sum(-1)
    np.fill_diagonal(dist, np.inf)
    nearest = dist.argmin(1)
    wrong = np.where(label[nearest] != label)[0]
    same_class, extent_gap, pairs = 0, [], collections.Counter()
    for i in wrong:
        a, b = shapes[shape_of[label[i]]], shapes[shape_of[label[nearest[i]]]]
        same_class += a["class"] == b["class"]
        extent_gap.append(np.abs(np.array(a["extent"]) - np.array(b["extent"])).max())
        pairs[(a["class"], b["class"])] += 1
    print(f"views {len(label)}, top-1 {1 - len(wrong) / len(label):.3f}, wrong {len(wrong)}, of the same class {same_class}")
    if extent_gap:
        q = np.percentile(extent_gap, [25, 50, 75])
        print(f"largest extent difference of a confused pair (m): p25 {q[0]:.2f}, median {q[1]:.2f}, p75 {q[2]:.2f}")
    for (a, b), n in pairs.most_common(10):
        print(f"  {a} -> {b}: {n}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: confusions.py VIEWS_DIR ROWS_CSV")
    main(sys.argv[1], sys.argv[2])
