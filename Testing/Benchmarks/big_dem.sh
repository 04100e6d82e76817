#!/usr/bin/env bash
# Big inputs through the command line: a SIZE x SIZE synthetic DEM (default 8192^2 = 67 Mcells)
# goes through `terroir fractal`, `terroir slope` and `terroir temperature` (and `gdaldem slope`
# as the peer), each under /usr/bin/time -v: wall time, peak resident memory, and that peak in
# units of one float32 copy of the elevation (4 B per cell). Then the memory check is shown at
# work: `terroir temperature` with TERROIR_MEMORY_LIMIT below its need is refused up front.
#   Testing/Benchmarks/big_dem.sh [BUILD_DIR] [SIZE]        (needs ~6 GiB of disk in $TMPDIR)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$here/build}
size=${2:-8192}
terroir="$build/bin/terroir"
[ -x "$terroir" ] || { echo "$terroir not found: build first" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "/usr/bin/time not found (Debian package time)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cells=$((size * size))

measure() { # measure LABEL command... -> one table row
  local label=$1; shift
  /usr/bin/time -v "$@" >"$work/out.txt" 2>"$work/time.txt" || {
    echo "$label failed:"; tail -3 "$work/time.txt"; return 1; }
  awk -v label="$label" -v cells="$cells" -F': ' '
    /Elapsed \(wall clock\)/ { n = split($2, p, ":"); wall = (n == 3) ? p[1]*3600 + p[2]*60 + p[3] : p[1]*60 + p[2] }
    /Maximum resident set size/ { rss = $2 * 1024 }
    END { printf "%-22s %9.2f %11.1f %11.0f %10.2f\n", label, wall, 1e3 * wall / (cells / 1e6),
          rss / 1048576, rss / (4 * cells) }' "$work/time.txt"
}

echo "terroir big-input benchmark: ${size} x ${size} = $(awk -v c=$cells 'BEGIN{printf "%.1f", c/1e6}') Mcells," \
  "$(nproc) cores, backend ${TERROIR_BACKEND:-auto}"
printf "%-22s %9s %11s %11s %10s\n" step seconds "ms/Mcell" "peak MiB" "peak/elev"
measure "terroir fractal" "$terroir" fractal "$work/dem.tif" --size "$size" --seed 7
measure "terroir slope" "$terroir" slope "$work/dem.tif" "$work/slope.tif"
if command -v gdaldem >/dev/null; then
  measure "gdaldem slope (peer)" gdaldem slope -compute_edges -q "$work/dem.tif" "$work/slope_gdal.tif"
fi
rm -f "$work/slope.tif" "$work/slope_gdal.tif"
measure "terroir temperature" "$terroir" temperature "$work/dem.tif" "$work/temperature.tif"
rm -f "$work/temperature.tif"
echo "peak/elev = peak resident memory / one float32 copy of the elevation (${cells} x 4 B)"
echo
echo "memory check: terroir temperature with TERROIR_MEMORY_LIMIT=1G"
status=0
TERROIR_MEMORY_LIMIT=1G "$terroir" temperature "$work/dem.tif" "$work/t.tif" 2>"$work/err.txt" ||
  status=$?
if [ "$status" -eq 0 ]; then
  echo "  not refused: the grid fits in 1 GiB"
else
  echo "  exit $status: $(grep -v '%$' "$work/err.txt")"
  [ -e "$work/t.tif" ] && echo "  PARTIAL OUTPUT LEFT" || echo "  no output written"
fi
