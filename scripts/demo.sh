#!/usr/bin/env bash
# The README demo: generate the small `demo` dataset (once), run the paper's
# pipeline on it (pipelines/demo.toml: lista.toml with the demo's folders),
# then score the run against the simulator's ground truth.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
DATA=${LISTA_DEMO_DATA:-data/demo}
OUT=${LISTA_DEMO_OUT:-out/demo}

if [ ! -f "$DATA/ground_truth.json" ]; then
  echo "demo: generating the demo dataset in $DATA" >&2
  "$BUILD/bin/lista-sim" --preset demo --out "$DATA" --seed 1
fi
"$BUILD/bin/lista-run" pipelines/demo.toml --dataset "$DATA" --out "$OUT"
echo
"$BUILD/bin/lista-eval" --dataset "$DATA" --run "$OUT"
echo
echo "demo: report written to $OUT/report.json, $OUT/report.html (open it in a browser) and $OUT/changes/"
