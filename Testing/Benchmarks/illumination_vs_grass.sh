#!/usr/bin/env bash
# Times GRASS GIS (r.horizon, r.sun) against `terroir bench --stages horizon,instant,monthly`
# on the same synthetic DEMs (terroir fractal, seed 1, 10 m cells: the DEM `terroir bench`
# generates internally), CPU only, and prints seconds, ms per million cells and ratios.
#   Testing/Benchmarks/illumination_vs_grass.sh [BUILD_DIR] [SIZES] [DAY]
# Defaults: build, "1024 2048", 80 (2025-03-21: its ~12.1 h of daylight equal the mean over the
# 15th of the 12 months at 39.4 N, and r.sun's time grows with the daylight steps).
# Not a CTest test: GRASS needs about 1 min at 1024^2 and 4-5 min at 2048^2 on 2 cores.
#
# GRASS side, in a temporary location (HOME points into the scratch folder: nothing is written
# to the user's GRASS settings). The fractal GeoTIFF has no CRS, so it is placed on NAD83 / UTM
# 11N at Sagehen Creek (upper-left 213980 E, 4373670 N; 39.4 N), where `terroir bench` puts its
# sun, so that r.sun has a latitude.
#  - r.horizon: ONE direction (45 deg, an oblique one), default sampling (distance=1, no
#    maxdistance); "x64" is that time multiplied by 64, an EXTRAPOLATION to the 64 sectors of
#    terroir's horizon map, not a measurement.
#  - r.sun: mode 2 (daily sums: no `time=`), day=DAY, shadowing from the DEM itself (no -p, no
#    horizon maps), slope and aspect from r.slope.aspect (timed apart and counted once), outputs
#    insol_time (hours of direct sun) and beam_rad (direct-beam Wh/m2/day) like terroir's
#    IlluminationHours and Insolation, step=0.5 h and step=0.1667 h (10 min, terroir's default
#    TimeStep); nprocs = the number of cores when this r.sun has the option.
#  - The 12-day figure is r.slope.aspect + 12 x one r.sun day: an EXTRAPOLATION of one day to
#    terroir's Monthly mode (the 15th of each month), not a measurement.
# terroir side: `terroir bench -s N -r 1 --backends cpu --stages horizon,instant,monthly --json`
# (best of 1 timed run after 1 warm-up): horizon = the 64-sector map alone; instant = one sun
# position with the map already built (HorizonMap) and by ray marching; monthly = 12 days in
# 10-minute steps, horizon map included.
# Ratios are GRASS time / terroir time (> 1: terroir is faster).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$here/build}
sizes=${2:-"1024 2048"}
day=${3:-80}
terroir="$build/bin/terroir"
python=${PYTHON:-/usr/bin/python3}
command -v grass >/dev/null || { echo "grass not found (Debian grass-core)" >&2; exit 1; }
command -v gdal_translate >/dev/null ||
  { echo "gdal_translate not found (Debian gdal-bin)" >&2; exit 1; }
[ -x "$terroir" ] || { echo "$terroir not found: build first" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/home"
cores=$(nproc)

version=$(HOME="$work/home" grass --version 2>&1 | head -1 || true)
echo "$version; terroir: $terroir; $cores cores; r.sun day $day"

run_grass() { # run_grass DEM SCRIPT: one GRASS session in a temporary location
  env -u GISRC -u GISBASE HOME="$work/home" TMPDIR="$work" LC_ALL=C \
    grass --tmp-location "$1" --exec bash "$2"
}

for n in $sizes; do
  echo
  echo "== $n x $n =="
  raw="$work/fractal_$n.tif"
  dem="$work/fractal_${n}_utm.tif"
  "$terroir" fractal "$raw" --size "$n" --seed 1 --spacing 10 --overwrite >/dev/null 2>&1
  gdal_translate -q -a_srs EPSG:26911 \
    -a_ullr 213980 4373670 $((213980 + 10 * n)) $((4373670 - 10 * n)) "$raw" "$dem"
  rm -f "$raw"

  times="$work/grass_times_$n.txt"
  cat >"$work/grass_$n.sh" <<EOF
set -e
tm() { # tm LABEL command...: appends "LABEL seconds" to $times
  local label=\$1; shift
  local t0 t1; t0=\$(date +%s.%N); "\$@"; t1=\$(date +%s.%N)
  awk -v l="\$label" -v a="\$t0" -v b="\$t1" 'BEGIN{ printf "%s %.3f\n", l, b - a }' >>"$times"
}
r.in.gdal -o input="$dem" output=dem --quiet
g.region raster=dem
np=""; r.sun --help 2>&1 | grep -q nprocs && np="nprocs=$cores"
hnp=""; r.horizon --help 2>&1 | grep -q nprocs && hnp="nprocs=$cores"
echo "r.sun threads: \${np:-1 (no nprocs option)}; r.horizon threads: \${hnp:-1 (no nprocs option)}" >&2
tm slope_aspect r.slope.aspect elevation=dem slope=slope aspect=aspect --quiet
tm horizon_1dir r.horizon elevation=dem direction=45 step=0 output=hz \$hnp --quiet
tm sun_30min r.sun elevation=dem slope=slope aspect=aspect day=$day step=0.5 \\
  insol_time=it30 beam_rad=b30 \$np --quiet
tm sun_10min r.sun elevation=dem slope=slope aspect=aspect day=$day step=0.1667 \\
  insol_time=it10 beam_rad=b10 \$np --quiet
EOF
  run_grass "$dem" "$work/grass_$n.sh" 2>&1 | grep -E "threads|ERROR|WARNING" || true
  [ "$(wc -l <"$times")" = 4 ] || { echo "GRASS run failed at $n x $n" >&2; exit 1; }

  json="$work/bench_$n.json"
  "$terroir" bench -s "$n" -r 1 --backends cpu --stages horizon,instant,monthly \
    --json "$json" >/dev/null 2>&1 ||
    { echo "terroir bench failed at $n x $n" >&2; exit 1; }

  "$python" - "$json" "$times" "$n" <<'PY'
import json
import sys

doc = json.load(open(sys.argv[1]))
g = dict((line.split()[0], float(line.split()[1])) for line in open(sys.argv[2]) if line.strip())
mc = int(sys.argv[3]) ** 2 / 1e6
nan = float("nan")
t = {}
for r in doc["results"]:
    if "seconds" in r:
        t[r["stage"]] = r
    else:
        print("terroir stage %s failed: %s" % (r.get("stage"), r.get("error")))


def row(what, grass_s=None, ours_s=None, note=""):
    """One line: seconds, ms per million cells, ratio GRASS / terroir when both are given."""
    cell = lambda v, f: (f % v) if v is not None else ""
    ratio = grass_s / ours_s if grass_s is not None and ours_s else None
    print(("%-44s %10s %10s %12s %13s %8s  %s" % (
        what, cell(grass_s, "%.3f"), cell(ours_s, "%.3f"),
        cell(None if grass_s is None else 1e3 * grass_s / mc, "%.1f"),
        cell(None if ours_s is None else 1e3 * ours_s / mc, "%.1f"), cell(ratio, "%.1f"),
        note)).rstrip())


print("%-44s %10s %10s %12s %13s %8s" % ("", "GRASS s", "terroir s", "GRASS ms/Mc",
                                          "terroir ms/Mc", "ratio"))
sectors = t.get("horizon", {}).get("sectors", 64)
row("r.horizon, 1 direction (measured)", g["horizon_1dir"])
row("horizon map, %d directions" % sectors, g["horizon_1dir"] * sectors,
    t.get("horizon", {}).get("seconds", nan), "GRASS: 1 direction x %d, EXTRAPOLATED" % sectors)
row("terroir instant (map cached)", None, t.get("instant", {}).get("seconds", nan))
row("terroir instant (ray marching)", None, t.get("instant-raymarch", {}).get("seconds", nan))
row("r.slope.aspect (input of r.sun)", g["slope_aspect"])
row("r.sun 1 day, step 0.5 h (measured)", g["sun_30min"])
row("r.sun 1 day, step 10 min (measured)", g["sun_10min"])
monthly = t.get("monthly", {})
m = monthly.get("seconds", nan)
note = "GRASS: slope/aspect + 12 x 1 day, EXTRAPOLATED"
row("12 days: r.sun 0.5 h steps vs monthly 10 min", g["slope_aspect"] + 12 * g["sun_30min"], m, note)
row("12 days, 10-min steps (monthly)", g["slope_aspect"] + 12 * g["sun_10min"], m, note)
print("terroir monthly: %s sun steps (12 x 24 h), horizon map %.3f s of it"
      % (monthly.get("sun_steps", "?"), monthly.get("horizon_map_seconds", nan)))
PY
done
echo
echo "ratio = GRASS time / terroir time (> 1: terroir is faster);"
echo "the x64 and 12-day GRASS figures are extrapolated from one GRASS run"
