#!/usr/bin/env python3
"""Which shapes a descriptor confuses: reads a lista-sim views folder and the
rows `lista-bench descriptors --rows DIR` wrote for one plugin, and prints
top-1, how many wrong nearest neighbours are of the same class, how far
their footprints/heights differ (largest extent difference, m) and the most
confused class pairs.

    bench/descriptors/confusions.py /tmp/desc-views /tmp/rows/describe.learned.csv

Plain Python (no numpy): a benchmark set has about a thousand views, a few
seconds of pairwise distances.
"""
import collections
import csv
import json
import statistics
import sys


def main(views_dir, rows_csv):
    index = json.load(open(f"{views_dir}/index.json"))
    shapes = {s["id"]: s for s in index["shapes"]}
    # Labels as lista's reader gives them: shapes numbered in order of first view.
    labels = {}
    for v in index["views"]:
        labels.setdefault(v["shape"], len(labels))
    shape_of = {label: shape for shape, label in labels.items()}
    with open(rows_csv, newline="") as f:
        table = list(csv.reader(f))[1:]
    label = [int(float(r[0])) for r in table]
    rows = [[float(x) for x in r[2:]] for r in table]
    nearest = []
    for i, a in enumerate(rows):
        best, best_j = float("inf"), -1
        for j, b in enumerate(rows):
            if j != i:
                d = sum((x - y) ** 2 for x, y in zip(a, b))
                if d < best:
                    best, best_j = d, j
        nearest.append(best_j)
    wrong = [i for i in range(len(label)) if label[nearest[i]] != label[i]]
    same_class, extent_gap, pairs = 0, [], collections.Counter()
    for i in wrong:
        a, b = shapes[shape_of[label[i]]], shapes[shape_of[label[nearest[i]]]]
        same_class += a["class"] == b["class"]
        extent_gap.append(max(abs(x - y) for x, y in zip(a["extent"], b["extent"])))
        pairs[(a["class"], b["class"])] += 1
    print(f"views {len(label)}, top-1 {1 - len(wrong) / len(label):.3f}, wrong {len(wrong)}, of the same class {same_class}")
    if extent_gap:
        # numpy's default (linear) percentiles; one value is its own quartiles
        q = statistics.quantiles(extent_gap, n=4, method="inclusive") if len(extent_gap) > 1 else extent_gap * 3
        print(f"largest extent difference of a confused pair (m): p25 {q[0]:.2f}, median {q[1]:.2f}, p75 {q[2]:.2f}")
    for (a, b), n in pairs.most_common(10):
        print(f"  {a} -> {b}: {n}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: confusions.py VIEWS_DIR ROWS_CSV")
    main(sys.argv[1], sys.argv[2])
