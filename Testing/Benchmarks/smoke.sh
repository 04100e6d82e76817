#!/usr/bin/env bash
# The benchmarks at a tiny size, so that they cannot rot unseen (CTest label `benchmarks`; the
# timings mean nothing at this size): `terroir bench` on every stage and backend, and every
# script of this folder (gdaldem, scikit-learn, the k-means core, RiverLand, GRASS's r.horizon and
# r.sun, GRASS's r.sim.water and r.sim.sediment against our erosion, the outputs of terroir run,
# the big-DEM memory run, erosion against real landscapes, and with an X display the scripted
# viewer session), each must run and write its results.
#   Testing/Benchmarks/smoke.sh BUILD_DIR SCRATCH_DIR
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$1
scratch=$2
rm -rf "$scratch"
mkdir -p "$scratch"
"$build/bin/terroir" bench --size 64 --repeat 1 --json "$scratch/bench.json" >"$scratch/bench.log"
/usr/bin/python3 - "$scratch/bench.json" <<'PY'
import json, sys
stages = {r["stage"] for r in json.load(open(sys.argv[1]))["results"]}
need = {"slope", "temperature", "horizon", "instant", "monthly", "infiltration", "humidity",
        "floodfill", "depressions", "flowacc", "waterflow", "kmeans"}
missing = need - stages
if missing:
    sys.exit("terroir bench wrote no result for " + ", ".join(sorted(missing)))
PY
bash "$here/Testing/Benchmarks/slope_vs_gdaldem.sh" "$build" "64" 1 >"$scratch/slope.log"
grep -q "ratio" "$scratch/slope.log" || { cat "$scratch/slope.log"; exit 1; }
/usr/bin/python3 "$here/Testing/Benchmarks/kmeans_vs_sklearn.py" --build "$build" --size 64 \
  --repeat 1 --ks 2 --compare-ks 2 --vtk-cells 4096 --json "$scratch/kmeans.json" \
  >"$scratch/kmeans.log"
test -s "$scratch/kmeans.json"
bash "$here/Testing/Benchmarks/kmeans_core.sh" "$build" 1 >"$scratch/kmeans_core.log"
grep -q "same" "$scratch/kmeans_core.log" || { cat "$scratch/kmeans_core.log"; exit 1; }
bash "$here/Testing/Benchmarks/riverland_bench.sh" "$build" 1 64 >"$scratch/riverland.log"
grep -q "yes" "$scratch/riverland.log" && ! grep -q "NO" "$scratch/riverland.log" ||
  { cat "$scratch/riverland.log"; exit 1; }
bash "$here/Testing/Benchmarks/illumination_vs_grass.sh" "$build" "64" 80 >"$scratch/grass.log"
grep -q "ratio" "$scratch/grass.log" || { cat "$scratch/grass.log"; exit 1; }
MINUTES=2 REPEAT=1 bash "$here/Testing/Benchmarks/erosion_vs_grass.sh" "$build" "64" 5 \
  >"$scratch/erosion_grass.log"
grep -q "GRASS r.sim.sediment" "$scratch/erosion_grass.log" ||
  { cat "$scratch/erosion_grass.log"; exit 1; }
# The erosion core's timing and bit-identity harness (built by hand, as its header says).
g++ -O2 -std=c++17 -pthread -I"$here/Filters/Terrain/Core" -I"$here/Common/Core" \
  "$here/Testing/Benchmarks/ErosionCoreTiming.cxx" "$build/lib/libTerroirTerrainCore.a" \
  "$build/lib/libTerroirCommonCore.a" -o "$scratch/erosion_timing"
"$scratch/erosion_timing" bench 64 2 1 >"$scratch/erosion_timing.log"
grep -q "hydraulic + thermal" "$scratch/erosion_timing.log" ||
  { cat "$scratch/erosion_timing.log"; exit 1; }
bash "$here/Testing/Benchmarks/run_outputs.sh" "$build" 64 >"$scratch/run_outputs.log"
grep -q "all identical" "$scratch/run_outputs.log" || { cat "$scratch/run_outputs.log"; exit 1; }
bash "$here/Testing/Benchmarks/big_dem.sh" "$build" 64 >"$scratch/big_dem.log"
grep -q "memory check" "$scratch/big_dem.log" || { cat "$scratch/big_dem.log"; exit 1; }
PYTHONPATH="$build/lib/python3/dist-packages" /usr/bin/python3 \
  "$here/Testing/Benchmarks/erosion_morphometry.py" "$build" "$scratch/erosion" 64 >"$scratch/erosion.log"
grep -q "fractal eroded" "$scratch/erosion.log" || { cat "$scratch/erosion.log"; exit 1; }
if [ -n "${DISPLAY:-}" ]; then
  /usr/bin/python3 "$here/Testing/Benchmarks/viewer_session.py" --build "$build" \
    --flow-iterations 10 --size 640x480 --skip-full --json "$scratch/viewer_session.json" \
    >"$scratch/viewer_session.log"
  grep -q "level of detail: slowest" "$scratch/viewer_session.log" || {
    cat "$scratch/viewer_session.log"
    exit 1
  }
  /usr/bin/python3 "$here/Testing/Benchmarks/viewer_erosion.py" --build "$build" --size 64 \
    --steps 10 --json "$scratch/viewer_erosion.json" >"$scratch/viewer_erosion.log" 2>&1
  grep -q "target 10 steps/s" "$scratch/viewer_erosion.log" || {
    cat "$scratch/viewer_erosion.log"
    exit 1
  }
fi
echo "benchmarks ran: $(ls "$scratch")"
