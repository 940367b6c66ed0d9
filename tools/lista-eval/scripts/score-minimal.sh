#!/usr/bin/env bash
# Runs the minimal pipeline on a dataset, scores it and the perfect run with
# lista-eval, and prints wall times with the machine load.
#   tools/lista-eval/scripts/score-minimal.sh BUILD_DIR DATASET [OUT]
# e.g. tools/lista-eval/scripts/score-minimal.sh build /work/data/demo /tmp/minimal-demo
set -euo pipefail
build=${1:?build dir}; data=${2:?dataset}; out=${3:-/tmp/lista-minimal-$(basename "$data")}
here=$(cd "$(dirname "$0")" && pwd)
echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
t0=$(date +%s.%N)
"$build/bin/lista-run" "$here/minimal.toml" --dataset "$data" --out "$out" --quiet
t1=$(date +%s.%N)
"$build/bin/lista-eval" --dataset "$data" --run "$out"
t2=$(date +%s.%N)
"$build/bin/lista-eval" --dataset "$data" --truth "$out.truth" >/dev/null
"$build/bin/lista-eval" --dataset "$data" --run "$out.truth" --json >"$out.truth.json"
t3=$(date +%s.%N)
printf 'lista-run %.2f s, lista-eval %.2f s, perfect run write+score %.2f s (load now: %s)\n' \
  "$(echo "$t1 - $t0" | bc)" "$(echo "$t2 - $t1" | bc)" "$(echo "$t3 - $t2" | bc)" "$(cut -d' ' -f1-3 /proc/loadavg)"
