#!/usr/bin/env python3
"""How far each reported object's floor (report.json `objects[].floor_z`, what
segment.complete measured) lies from the true floor.

  bench/segmentation/floor_error.py DATASET RUN [DATASET RUN ...]

The true floor is the world plane z = 0 of a simulated dataset (lista-sim
scenes stand on it; ground_truth.json's `mission_to_world` places each
mission), taken into the common frame through the report's alignment and
read under each object's centroid. Prints per run the objects given a floor
and the error's median, median absolute value, 90th percentile and maximum
(metres). Descriptors measure heights from floor_z (docs/descriptors.md);
lista-bench descriptors --floor-error shows what an error of this size costs.
Plain Python 3 (no numpy).
"""
import json
import statistics
import sys


def rigid_inverse(m):
    r = [[m[j][i] for j in range(3)] for i in range(3)]  # R transposed
    t = [-sum(r[i][k] * m[k][3] for k in range(3)) for i in range(3)]
    return [r[0] + [t[0]], r[1] + [t[1]], r[2] + [t[2]], [0.0, 0.0, 0.0, 1.0]]


def multiply(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def floor_height(world_to_common, x, y):
    """z of the world plane z = 0, in the common frame, under (x, y)."""
    n = [world_to_common[i][2] for i in range(3)]  # the plane's normal, turned
    q = [world_to_common[i][3] for i in range(3)]  # a point on it (world origin)
    return q[2] - (n[0] * (x - q[0]) + n[1] * (y - q[1])) / n[2]


def errors(dataset, run):
    truth = json.load(open(f"{dataset}/ground_truth.json"))
    report = json.load(open(f"{run}/report.json"))
    out = []
    for o in report["objects"]:
        if o.get("floor_z") is None:
            continue
        m = o["mission"]
        world_to_common = multiply(report["alignment"][m], rigid_inverse(truth["mission_to_world"][m]))
        out.append(o["floor_z"] - floor_height(world_to_common, o["centroid"][0], o["centroid"][1]))
    return len(report["objects"]), out


def main(args):
    if len(args) < 2 or len(args) % 2:
        sys.exit(__doc__)
    print("| run | objects | given a floor | error median (m) | abs median | abs p90 | abs max |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for dataset, run in zip(args[::2], args[1::2]):
        total, e = errors(dataset, run)
        if not e:
            print(f"| {run} | {total} | 0 | - | - | - | - |")
            continue
        a = sorted(abs(v) for v in e)
        p90 = a[min(len(a) - 1, int(0.9 * (len(a) - 1) + 0.5))]
        print(f"| {run} | {total} | {len(e)} | {statistics.median(e):.3f} | {statistics.median(a):.3f} "
              f"| {p90:.3f} | {a[-1]:.3f} |")


if __name__ == "__main__":
    main(sys.argv[1:])
