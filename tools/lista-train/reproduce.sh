#!/usr/bin/env bash
# Reproduces the shipped describe.learned weights from scratch:
#   tools/lista-train/reproduce.sh [BUILD_DIR] [OUT_FILE]
# BUILD_DIR (default: build) must hold bin/lista-sim and bin/lista-train;
# OUT_FILE defaults to models/describe-learned.bin (+ .sha256). The views sets
# go to ${LISTA_VIEWS_DIR:-/tmp/lista-train-views}/{single,pass,furniture-single,
# furniture-pass,single-5,pass-5,...} (18 folders, about 4 GB); $LISTA_SIM may
# name a lista-sim built elsewhere. Everything is seeded:
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
# Procedural objects, seven seeds (1, 5, 7, 9, 11, 15, 17): per seed 600 instances
# (about 195 shape ids once identical meshes and look-alikes within 2 cm share
# one; about 35 held out by the simulator's val/test split) x 8 partial views
# from random viewpoints and sensors, once as single sweeps and once as 5
# sweeps merged along a pass (what a mission map holds of an object). Seeds
# draw different shapes, and a shape's split follows from its id, so no seed
# trains on another's held-out shapes. Real furniture, seeds 1 and 5: 600
# instances of the Sweet Home 3D models each (472 readable, 62 held out for
# every seed), the same two ways; tools/fetch-shapes.sh downloads Debian's
# sweethome3d-furniture into $LISTA_SHAPES_DIR (default
# ~/.cache/lista/shapes) once. The network trains on all folders as one set.
# Why seven procedural seeds: held-out accuracy grew with the number of
# training shapes, not with steps or width (docs/bench/descriptors.md).
# The head reads all ten shape globals (canonical.hpp) and measures heights
# from the floor the views stand on, which it withholds from 20 % of the
# training views (--floor-dropout 0.2) so that objects of unknown floor are
# still described well. Models before 2026-11-26 were trained with
# --globals 9 --no-floor, before 2026-11-25 (evening) with --globals 4.
shapes="${LISTA_SHAPES_DIR:-$HOME/.cache/lista/shapes}"
sh "$root/tools/fetch-shapes.sh" "$shapes" >&2
folders=()
make_views() {  # name, seed, extra lista-sim options
  local name=$1 seed=$2; shift 2
  "$sim" views --out "$views/$name" --objects 600 --views-per-object 8 --seed "$seed" --threads 2 --overwrite "$@"
  "$sim" views --out "$views/${name/single/pass}" --objects 600 --views-per-object 8 --seed "$seed" --threads 2 \
    --overwrite --scans-per-view 5 "$@"
  folders+=("$views/$name" "$views/${name/single/pass}")
}
make_views single 1
make_views furniture-single 1 --furniture "$shapes" --no-procedural
for seed in 5 7 9 11; do make_views "single-$seed" "$seed"; done
make_views furniture-single-5 5 --furniture "$shapes" --no-procedural
# Seeds 15 and 17 came last. The folder order numbers the shapes, and the
# numbering decides which shapes each batch draws: a new order is a new
# training run, not a reproduction.
for seed in 15 17; do make_views "single-$seed" "$seed"; done
"$build/bin/lista-train" --views "${folders[@]}" \
  --out "$out" --overwrite --globals 10 --floor-dropout 0.2 --loss triplet --margin 0.5 --ema 0.999 --steps 16000 --eval-every 2000 --seed 1 --threads 1
