# Sourced by Scripts/validate_with_grass.sh and validate_with_saga.sh (after setting `here` to
# the source tree): the terroir program (TERROIR, else build/bin/terroir), the DEM (--dem DEM as
# the first arguments, else the bundled Sagehen DEM; `dem_args` is what terroir validate gets),
# and a scratch folder `tmp` removed on exit. Leaves the remaining arguments in "$@".
terroir=${TERROIR:-$here/build/bin/terroir}
dem_args=()
dem=$here/Data/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif
if [ "${1:-}" = "--dem" ]; then
  dem=$2
  dem_args=("$dem")
  shift 2
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
