#!/usr/bin/env bash
# Reproduces the shipped describe.learned weights from scratch:
#   tools/lista-train/reproduce.sh [BUILD_DIR] [OUT_FILE]
# BUILD_DIR (default: build) must hold bin/lista-sim and bin/lista-train;
# OUT_FILE defaults to models/describe-learned.bin (+ .sha256). The views sets
# go to ${LISTA_VIEWS_DIR:-/tmp/lista-train-views}/{single,pass,furniture-single,furniture-pass}; $LISTA_SIM
# may name a lista-sim built elsewhere. Everything is seeded:
# the same build, seed and thread count give the same weights byte for byte.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
out="${2:-$root/models/describe-learned.bin}"
views="${LISTA_VIEWS_DIR:-/tmp/lista-train-views}"
sim="${LISTA_SIM:-$build/bin/lista-sim}"
for exe in "$sim" "$build/bin/lista-train"; do
  [[ -x "$exe" ]] || { echo "reproduce.sh: $exe not built" >&2; exit 1; }
done
# Procedural objects: 600 instances (198 shape ids once identical meshes and
# look-alikes within 2 cm share one, 35 held out by the simulator's val/test
# split) x 8 partial views from random viewpoints and
# sensors, once as single sweeps and once as 5 sweeps merged along a pass
# (what a mission map holds of an object). Real furniture: 600 instances of
# the Sweet Home 3D models (339 of 472 drawn, 338 ids, 62 held out), the same two
# ways; tools/fetch-shapes.sh downloads Debian's sweethome3d-furniture into
# $LISTA_SHAPES_DIR (default ~/.cache/lista/shapes) once. The network trains
# on all four folders as one set.
shapes="${LISTA_SHAPES_DIR:-$HOME/.cache/lista/shapes}"
sh "$root/tools/fetch-shapes.sh" "$shapes" >&2
"$sim" views --out "$views/single" --objects 600 --views-per-object 8 --seed 1 --threads 2 --overwrite
"$sim" views --out "$views/pass" --objects 600 --views-per-object 8 --seed 1 --threads 2 --overwrite --scans-per-view 5
"$sim" views --out "$views/furniture-single" --objects 600 --views-per-object 8 --seed 1 --threads 2 --overwrite \
  --furniture "$shapes" --no-procedural
"$sim" views --out "$views/furniture-pass" --objects 600 --views-per-object 8 --seed 1 --threads 2 --overwrite \
  --furniture "$shapes" --no-procedural --scans-per-view 5
"$build/bin/lista-train" --views "$views/single" "$views/pass" "$views/furniture-single" "$views/furniture-pass" \
  --out "$out" --loss triplet --steps 16000 --eval-every 2000 --seed 1 --threads 1
