#!/usr/bin/env python3
"""Which true objects a run reports in pieces.

  bench/segmentation/split.py DATASET RUN [RUN...]

For every reported object (changes/<mission>.pcd, `object` column) finds
the true object (scan `label`) that holds at least half of its points. A
true object that is the majority of two or more reports in one mission is
split: each piece is a report of its own, and at most one of them can pair
with it (lista-eval pairs at IoU > 0.5). Prints, per run, the number of
split (mission, true object) and each with its reports (id, points).
Plain Python 3 (no numpy); reads binary/ascii PCD, not compressed.
"""
import json, os, sys
from collections import Counter, defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from missed import read_pcd  # noqa: E402


def splits(dataset, run):
    found = []
    for m in sorted(os.listdir(dataset)):
        scans_dir = os.path.join(dataset, m, "scans")
        changes = os.path.join(run, "changes", m + ".pcd")
        if not os.path.isdir(scans_dir) or not os.path.exists(changes):
            continue
        c = read_pcd(changes, ["scan", "index", "object"])
        files = sorted(os.listdir(scans_dir))
        wanted = defaultdict(list)
        for s, i, o in zip(c["scan"], c["index"], c["object"]):
            if o >= 0:
                wanted[s].append((i, o))
        labels_of = defaultdict(Counter)
        for s, points in wanted.items():
            label = read_pcd(os.path.join(scans_dir, files[s]), ["label"])["label"]
            for i, o in points:
                labels_of[o][label[i]] += 1
        pieces = defaultdict(list)
        for o, counts in labels_of.items():
            label, n = counts.most_common(1)[0]
            if label != 0 and 2 * n >= sum(counts.values()):
                pieces[label].append((o, sum(counts.values())))
        found += [(m, label, sorted(p)) for label, p in sorted(pieces.items()) if len(p) >= 2]
    return found


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    dataset = sys.argv[1]
    if not os.path.exists(os.path.join(dataset, "ground_truth.json")):
        sys.exit(f"split.py: error: {dataset}: no ground_truth.json (give a lista-sim dataset)")
    for run in sys.argv[2:]:
        if not os.path.exists(os.path.join(run, "report.json")):
            sys.exit(f"split.py: error: {run}: no report.json (give a lista-run output folder)")
        found = splits(dataset, run)
        print(f"{run}: {len(found)} true objects split")
        for m, label, pieces in found:
            print(f"  mission {m}, true object {label}: reports " + ", ".join(f"{o} ({n} points)" for o, n in pieces))
