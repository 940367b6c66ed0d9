#!/usr/bin/env bash
# End-to-end measurement: runs a pipeline (default pipelines/lista.toml) on
# each dataset, scores it with lista-eval and prints one markdown table
# (per-point scores beside the paper's, object-level scores), and per run a
# stage table: wall time (report.json's timings_s) and the process's peak
# RSS at the stage's end (its log line) beside the budget and the last
# record in bench/e2e/budgets.json; "over" marks a stage past its budget.
#   bench/e2e/run.sh [BUILD_DIR] [DATASET_DIR...]
# defaults: BUILD_DIR=build, datasets /work/data/exp1 /work/data/exp2 /work/data/exp3
# env: PIPELINE (default pipelines/lista.toml), OUT (default /tmp/lista-e2e-bench),
#      THREADS (default: all cores)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-build}
shift || true
datasets=("$@")
[ ${#datasets[@]} -gt 0 ] || datasets=(/work/data/exp1 /work/data/exp2 /work/data/exp3)
pipeline=${PIPELINE:-$root/pipelines/lista.toml}
out=${OUT:-/tmp/lista-e2e-bench}
threads=${THREADS:-$(nproc)}
for b in lista-run lista-eval; do
  [ -x "$build/bin/$b" ] || { echo "run.sh: error: $build/bin/$b not built (ninja -C $build lista-run lista-eval and the plugins)" >&2; exit 2; }
done

mkdir -p "$out"
for d in "${datasets[@]}"; do
  name=$(basename "$d")
  rm -rf "${out:?}/$name"
  load=$(uptime | sed 's/.*load average: //')
  start=$(date +%s.%N)
  "$build/bin/lista-run" "$pipeline" --dataset "$d" --out "$out/$name" --threads "$threads" 2> "$out/$name.log"
  wall=$(python3 -c "print(round($(date +%s.%N) - $start, 3))")
  echo "{\"wall_s\": $wall, \"load_before\": \"$load\", \"threads\": $threads}" > "$out/$name/wall.json"
  "$build/bin/lista-eval" --dataset "$d" --run "$out/$name" --json > "$out/$name/score.json"
  echo "$name: $wall s wall, load before: $load" >&2
done

python3 - "$out" "$pipeline" "$root/bench/e2e/budgets.json" "${datasets[@]}" <<'PY'
import json, os, re, statistics, sys
out, pipeline, budgets_file, datasets = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
budgets = json.load(open(budgets_file))
# The paper's Table (Exp. 1-3): precision, recall, F1, IoU.
paper = {"exp1": (0.89, 0.68, 0.77, 0.63), "exp2": (0.82, 0.95, 0.88, 0.79), "exp3": (0.76, 0.55, 0.63, 0.55)}
def f(v): return "n/a" if v is None else f"{v:.3f}"
def pf(name, i): return f"{paper[name][i]:.2f}" if name in paper else "-"
print(f"pipeline: {os.path.relpath(pipeline)}\n")
print("| dataset | P (paper) | R (paper) | Spec | F1 (paper) | IoU (paper) | status acc | match acc | t err med (m) | r err med (deg) | wall (s) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
timings = {}
for d in datasets:
    name = os.path.basename(d.rstrip("/"))
    s = json.load(open(f"{out}/{name}/score.json"))
    w = json.load(open(f"{out}/{name}/wall.json"))
    r = json.load(open(f"{out}/{name}/report.json"))
    timings[name] = r.get("timings_s", {})
    p = s["points"]
    objs = s["objects"]
    # Object-level scores pooled over missions, weighted by pairs / moved objects.
    paired = sum(o["paired"] for o in objs)
    status = sum((o["status_accuracy"] or 0) * o["paired"] for o in objs) / paired if paired else None
    moved = sum(o["moved"] for o in objs)
    match = sum((o["match_accuracy"] or 0) * o["moved"] for o in objs) / moved if moved else None
    terr = [o["translation_error_m"]["median"] for o in objs if o["translation_error_m"]["median"] is not None]
    rerr = [o["rotation_error_deg"]["median"] for o in objs if o["rotation_error_deg"]["median"] is not None]
    print(f"| {name} | {f(p['precision'])} ({pf(name,0)}) | {f(p['recall'])} ({pf(name,1)}) | {f(p['specificity'])} "
          f"| {f(p['f1'])} ({pf(name,2)}) | {f(p['iou'])} ({pf(name,3)}) | {f(status)} | {f(match)} "
          f"| {f(statistics.median(terr) if terr else None)} | {f(statistics.median(rerr) if rerr else None)} "
          f"| {w['wall_s']:.1f} (load {w['load_before'].split(',')[0]}) |")
# Per run: each stage's time and peak memory beside its budget and record.
done = re.compile(r"info: (\S+) \(\S+\) done in ([0-9.]+) s, peak RSS ([0-9]+) MiB")
def cell(v, fmt="{:.1f}"): return "-" if v is None else fmt.format(v)
for name, t in timings.items():
    peaks = {m.group(1): int(m.group(3)) for m in done.finditer(open(f"{out}/{name}.log").read())}
    b = budgets.get(name, {})
    rows = [(k, t[k], peaks.get(k)) for k in t]
    rows.append(("total", sum(t.values()), max(peaks.values()) if peaks else None))
    print(f"\nstages of {name}: seconds and peak RSS (MiB) beside the budget and the last record\n")
    print("| stage | s | budget s | record s | peak MiB | budget MiB | record MiB | |")
    print("|---|---|---|---|---|---|---|---|")
    for k, sec, mib in rows:
        e = b.get(k, {})
        over = (e.get("budget_s") is not None and sec > e["budget_s"]) or (
            e.get("budget_mib") is not None and mib is not None and mib > e["budget_mib"])
        print(f"| {k} | {sec:.2f} | {cell(e.get('budget_s'))} | {cell(e.get('record_s'), '{:.2f}')} | {cell(mib, '{}')} "
              f"| {cell(e.get('budget_mib'), '{}')} | {cell(e.get('record_mib'), '{}')} | {'over' if over else ''} |")
PY
