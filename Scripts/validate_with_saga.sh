#!/usr/bin/env bash
# `terroir validate` with SAGA GIS's flow accumulations as further methods, when SAGA is
# installed (Debian package saga): SAGA fills the DEM (ta_preprocessor 4, Fill Sinks (Wang &
# Liu)), computes Flow Accumulation (Top-Down) (ta_hydrology 0, cell area = m2 on a metric grid)
# with METHOD 0 D8, 4 MFD (convergence 1.1, no contour-length weights), 3 its "Deterministic
# Infinity" (an aspect split, not Tarboton's facets) and 5 Multiple Triangular Flow Direction
# (Seibert & McGlynn 2007, Tarboton's facets), and hands them to terroir with --peer (the
# terroir program itself never runs other programs).
# Usage: Scripts/validate_with_saga.sh [--dem DEM] [terroir validate options...]
#   (without --dem: the bundled Sagehen DEM, its NHD flowlines and its watershed)
# Fill Sinks' minimum slope: SAGA_MINSLOPE (degrees) if set, else one float32 step of the DEM's
# highest elevation per cell, at least 0.001 degree (Testing/Python/TerroirSaga.py,
# min_slope_degrees: smaller rounds to flat flats, SAGA's default 0.1 steepens gentle valleys).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
. "$here/Scripts/validate_peer_args.sh"
command -v saga_cmd > /dev/null ||
  { echo "SAGA GIS is not installed (no saga_cmd, Debian package saga):" \
      "run terroir validate alone" >&2; exit 1; }
minslope=${SAGA_MINSLOPE:-$(gdalinfo -mm "$dem" 2> /dev/null | awk '
  /^Pixel Size/ { gsub(/[(),=]/, " "); dx = $3 < 0 ? -$3 : $3 + 0; dy = $4 < 0 ? -$4 : $4 + 0 }
  /Computed Min\/Max=/ { split(substr($0, index($0, "=") + 1), m, ",")
                         lo = m[1] < 0 ? -m[1] : m[1]; hi = m[2] < 0 ? -m[2] : m[2] }
  END { z = lo > hi ? lo : hi; if (z < 1) z = 1; cell = dx < dy ? dx : dy
        if (cell <= 0) { print 0.001; exit }
        e = int(log(z) / log(2)); if (2 ^ e > z) e--  # floor(log2 z)
        s = atan2(2 ^ (e - 23), cell) * 180 / atan2(0, -1)
        printf "%.6g\n", (s > 0.001 ? s : 0.001) }')}
saga() {
  echo "\$ saga_cmd $*" >> "$tmp/saga.log"
  saga_cmd -f=q "$@" >> "$tmp/saga.log" 2>&1 || { cat "$tmp/saga.log" >&2; exit 1; }
}
saga ta_preprocessor 4 -ELEV "$dem" -FILLED "$tmp/filled.tif" -MINSLOPE "$minslope"
for m in 0 3 4 5; do
  saga ta_hydrology 0 -ELEVATION "$tmp/filled.tif" -FLOW "$tmp/acc$m.tif" -METHOD $m \
    -CONVERGENCE 1.1 -MFD_CONTOUR 0 -FLOW_UNIT 1
done
echo "SAGA: Fill Sinks (Wang & Liu) MINSLOPE $minslope degrees, Flow Accumulation (Top-Down)"
"$terroir" validate "${dem_args[@]}" --peer "SAGA D8=$tmp/acc0.tif" \
  --peer "SAGA MFD=$tmp/acc4.tif" --peer "SAGA D-infinity=$tmp/acc3.tif" \
  --peer "SAGA MTFD=$tmp/acc5.tif" "$@"
