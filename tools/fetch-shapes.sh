#!/bin/sh
# Unpacks Debian's sweethome3d-furniture meshes (OBJ, y-up, in cm) into a cache
# folder that `lista-sim views --furniture DIR` reads (default
# ~/.cache/lista/shapes).
# Quick when already done. Usage: tools/fetch-shapes.sh [cache_dir]
set -eu
cache="${1:-${LISTA_SHAPES_DIR:-$HOME/.cache/lista/shapes}}"
stamp="$cache/.unpacked"
if [ -f "$stamp" ]; then
  echo "shapes already in $cache"
  exit 0
fi
mkdir -p "$cache/deb"
cd "$cache/deb"
if ! ls sweethome3d-furniture_*.deb >/dev/null 2>&1; then
  apt-get download sweethome3d-furniture || {
    echo "fetch-shapes: apt-get download sweethome3d-furniture failed (no network or package index?)" >&2
    exit 1
  }
fi
rm -rf "$cache/root"
dpkg -x sweethome3d-furniture_*.deb "$cache/root"
# The meshes ship inside zip catalogues (.sh3f furniture libraries in
# Debian 12's package, .jar in older ones): unpack each into its own folder,
# next to its PluginFurnitureCatalog.properties.
command -v unzip >/dev/null || { echo "fetch-shapes: needs unzip (apt-get install unzip)" >&2; exit 1; }
find "$cache/root" \( -name '*.sh3f' -o -name '*.jar' \) | while read -r lib; do
  name=$(basename "$lib"); name=${name%.*}
  dir="$cache/unpacked/$name"
  mkdir -p "$dir"
  (cd "$dir" && unzip -qo "$lib")
done
count=$(find "$cache" -iname '*.obj' | wc -l)
if [ "$count" -eq 0 ]; then
  echo "fetch-shapes: no OBJ meshes found in the package" >&2
  exit 1
fi
touch "$stamp"
echo "unpacked $count OBJ meshes into $cache"
