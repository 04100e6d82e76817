#!/usr/bin/env bash
# `terroir validate` with GRASS r.watershed (single flow direction, -s) as a third method, when
# GRASS is installed: r.watershed's accumulation is computed here and handed to terroir with
# --peer (the terroir program itself never runs other programs).
# Usage: Scripts/validate_with_grass.sh [--dem DEM] [terroir validate options...]
#   (without --dem: the bundled Sagehen DEM, its NHD flowlines and its watershed)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
. "$here/Scripts/validate_peer_args.sh"
command -v grass > /dev/null || { echo "GRASS is not installed: run terroir validate alone" >&2; exit 1; }
grass --tmp-location "$dem" --exec bash -c "
  r.in.gdal -o input='$dem' output=dem --quiet &&
  g.region raster=dem &&
  r.watershed -s elevation=dem accumulation=acc --quiet &&
  r.out.gdal input=acc output='$tmp/acc.tif' format=GTiff type=Float64 --quiet" > "$tmp/grass.log" 2>&1 ||
  { cat "$tmp/grass.log" >&2; exit 1; }
"$terroir" validate "${dem_args[@]}" --peer "r.watershed=$tmp/acc.tif" "$@"
