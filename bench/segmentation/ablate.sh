#!/usr/bin/env bash
# Segmentation ablation: runs bench/segmentation/ablate.toml (one difference,
# many filter/segmenter branches) on each dataset, scores every branch with
# lista-eval and prints one markdown table.
#   bench/segmentation/ablate.sh [BUILD_DIR] [DATASET_DIR...]
# defaults: BUILD_DIR=build, datasets /work/data/exp1 /work/data/exp2 /work/data/exp3
# env: OUT (scratch folder, default /tmp/lista-seg-ablate), THREADS (default: all cores)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
shift || true
datasets=("$@")
[ ${#datasets[@]} -gt 0 ] || datasets=(/work/data/exp1 /work/data/exp2 /work/data/exp3)
out=${OUT:-/tmp/lista-seg-ablate}
threads=${THREADS:-$(nproc)}
run="$build/bin/lista-run"
eval_bin="$build/bin/lista-eval"
for b in "$run" "$eval_bin"; do
  [ -x "$b" ] || { echo "ablate.sh: error: $b not built (ninja -C $build lista-run lista-eval and the plugins)" >&2; exit 2; }
done

# branch name -> its stages after the shared read/align/difference (for timing)
branches=(volumetric no_filters no_roi no_ground no_morphology plain_opening no_overlap no_complete no_carve no_recomplete no_comove full euclidean region_growing mls)
declare -A stages=(
  [volumetric]="segment_raw" [no_filters]="segment_raw"
  [no_roi]="ground_nr clean_nr segment_nr overlap_nr complete_no_roi"
  [no_ground]="roi clean_ng segment_ng overlap_ng complete_no_ground"
  [no_morphology]="roi ground segment_nm overlap_nm complete_no_morphology"
  [plain_opening]="roi ground clean_open segment_open overlap_open complete_plain_opening"
  [no_overlap]="roi ground clean segment complete_no_overlap" [no_complete]="roi ground clean segment overlap"
  [no_carve]="roi ground clean segment overlap complete"
  [no_recomplete]="roi ground clean segment overlap complete carve"
  [no_comove]="roi ground clean segment overlap complete carve recomplete"
  [full]="roi ground clean segment overlap complete carve recomplete comove"
  [euclidean]="roi ground clean segment_eu overlap_eu complete_euclidean"
  [region_growing]="roi ground clean segment_rg overlap_rg complete_region_growing"
  [mls]="roi ground smooth clean_mls segment_mls overlap_mls complete_mls")

rm -rf "$out"
mkdir -p "$out"
echo "load before: $(uptime)" >&2
for d in "${datasets[@]}"; do
  name=$(basename "$d")
  sets=()
  for b in "${branches[@]}"; do sets+=(--set "report_$b.path=\"$out/$name/$b\""); done
  start=$(date +%s.%N)
  "$run" "$here/ablate.toml" --dataset "$d" --out "$out/$name" --threads "$threads" -q "${sets[@]}"
  echo "$name: pipeline $(echo "$(date +%s.%N) - $start" | bc) s, load: $(uptime | sed 's/.*load average: //')" >&2
  for b in "${branches[@]}"; do
    "$eval_bin" --dataset "$d" --run "$out/$name/$b" --json > "$out/$name/$b/score.json"
  done
done

python3 - "$out" "${branches[*]}" "$(declare -p stages)" "${datasets[@]}" <<'PY'
import json, os, re, sys
out, branches, stage_decl, datasets = sys.argv[1], sys.argv[2].split(), sys.argv[3], sys.argv[4:]
stages = dict(re.findall(r'\[(\w+)\]="([^"]*)"', stage_decl))
def f(v): return "n/a" if v is None else f"{v:.3f}"
print("| dataset | branch | point P | point R | point F1 | point IoU | objects reported | true changed | pairs | object P | object R | branch time (s) |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for d in datasets:
    name = os.path.basename(d.rstrip("/"))
    for b in branches:
        s = json.load(open(f"{out}/{name}/{b}/score.json"))
        r = json.load(open(f"{out}/{name}/{b}/report.json"))
        p, o = s["points"], [x for x in s["objects"] if x["mission"] == "all"][0]
        t = sum(r.get("timings_s", {}).get(st, 0.0) for st in stages[b].split())
        print(f"| {name} | {b} | {f(p['precision'])} | {f(p['recall'])} | {f(p['f1'])} | {f(p['iou'])} | "
              f"{o['reported']} | {o['true_changed']} | {o['paired']} | {f(o['precision'])} | {f(o['recall'])} | {t:.2f} |")
PY
