#!/usr/bin/env bash
# Times `terroir slope` against `gdaldem slope` on the same synthetic GeoTIFFs, whole process
# each (read, compute, write), best of REPEAT runs, and prints the ratio.
#   Testing/Benchmarks/slope_vs_gdaldem.sh [BUILD_DIR] [SIZES] [REPEAT]
# Defaults: build, "2048 4096", 3. Both tools compute edges (gdaldem -compute_edges) and write
# a Float32 GeoTIFF; terroir runs with its default backend (TERROIR_BACKEND=cpu|gpu to force).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$here/build}
sizes=${2:-"2048 4096"}
repeat=${3:-3}
terroir="$build/bin/terroir"
command -v gdaldem >/dev/null || { echo "gdaldem not found (Debian gdal-bin)" >&2; exit 1; }
[ -x "$terroir" ] || { echo "$terroir not found: build first" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

best_of() { # best_of N command... -> prints best wall seconds
  local n=$1 best=""; shift
  for _ in $(seq "$n"); do
    rm -f "$work/out.tif"
    local t0 t1
    t0=$(date +%s.%N); "$@" >/dev/null 2>&1; t1=$(date +%s.%N)
    best=$(awk -v a="$best" -v t0="$t0" -v t1="$t1" 'BEGIN{ d=t1-t0; if (a=="" || d<a) print d; else print a }')
  done
  echo "$best"
}

printf "%-6s %8s %12s %12s %8s %14s %14s\n" size Mcells terroir_s gdaldem_s ratio terroir_ms/Mc gdaldem_ms/Mc
for n in $sizes; do
  dem="$work/fractal_$n.tif"
  "$terroir" fractal "$dem" --size "$n" --seed 7 >/dev/null 2>&1
  tt=$(best_of "$repeat" "$terroir" slope "$dem" "$work/out.tif" --overwrite)
  tg=$(best_of "$repeat" gdaldem slope -compute_edges -of GTiff "$dem" "$work/out.tif")
  awk -v n="$n" -v tt="$tt" -v tg="$tg" 'BEGIN{ mc=n*n/1e6;
    printf "%-6d %8.2f %12.3f %12.3f %8.2f %14.1f %14.1f\n", n, mc, tt, tg, tg/tt, 1e3*tt/mc, 1e3*tg/mc }'
done
echo "ratio = gdaldem time / terroir time (> 1: terroir is faster)"
