#!/usr/bin/env bash
# Every distributed stage in one chain, in pieces and serially, on a SIZE^2 fractal DEM (issue
# 25; Documentation/Scaling.md, "The whole chain in pieces"): DistributedChain.py's `full`
# recipe (sun, slope, temperature, infiltration, soil humidity, flood fill, D8 flow
# accumulation, water flow in Pulse mode for FLOW_ITERATIONS iterations, k-means) under
# `mpirun --oversubscribe -np NP pvbatch --symmetric`, then CompareDistributed.py, which runs
# the same chain serially with the standalone build and requires the pieces to equal it (bit
# for bit; D8's areas within 1e-12). Prints the wall times and each process's peak resident
# memory (the serial run's too), per million cells.
#   Testing/Benchmarks/full_chain_mpi.sh [PARAVIEW_BUILD] [OUT_DIR] [SIZE] [NP] [FLOW_ITERATIONS]
# Defaults: build-paraview, a new temporary folder, 1024, 4 ranks, 50 iterations. Needs gdal-bin
# (gdal_translate gives the fractal a place: UTM 11 N, as Sagehen), the
# ParaView tree (its plugin and paraview-prefix) and the standalone build (TERROIR_STANDALONE_BUILD,
# default build/). The ParaView tree's FullChainBenchmarkSmoke runs it at 192^2 on 2 ranks.
# Memory (measured at 4096^2): about 0.6 kB per cell in the pieces (all ranks together, plus
# 0.35 GB of pvbatch per rank) and 0.53 kB per cell serially, one after the other; each rank's
# rank<R>.json records every stage's resident memory (stage_memory). TERROIR_TRIM=1 calls
# malloc_trim before each stage (to see the live memory between stages; the peak is the same).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
pvbuild=${1:-$here/build-paraview}
out=${2:-$(mktemp -d)}
size=${3:-1024}
np=${4:-4}
iterations=${5:-50}
standalone=${TERROIR_STANDALONE_BUILD:-$here/build}
pvbatch=$pvbuild/paraview-prefix/usr/bin/pvbatch
plugin=$pvbuild/lib/paraview-5.11/plugins/Terroir/Terroir.so
terroir=$standalone/bin/terroir
for f in "$pvbatch" "$plugin" "$terroir"; do
  [ -e "$f" ] || { echo "$f not found: build the ParaView and standalone trees first" >&2; exit 1; }
done
mkdir -p "$out"
dem=$out/fractal$size.tif
if [ ! -e "$dem" ]; then
  # The sun needs a place on Earth: the fractal (10 m cells) put in UTM zone 11 N, where Sagehen
  # Creek lies.
  "$terroir" fractal "$out/plain$size.tif" --size "$size" --seed 7 --overwrite >/dev/null
  gdal_translate -q -a_srs EPSG:32611 -a_ullr 215000 $((4380000 + 10 * size)) \
    $((215000 + 10 * size)) 4380000 "$out/plain$size.tif" "$dem"
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1
export TERROIR_FLOW_ITERATIONS=$iterations
site=$pvbuild/paraview-prefix/usr/lib/python3/dist-packages
run=$out/np$np
rm -rf "$run"
mkdir -p "$run"
t0=$(date +%s.%N)
TERROIR_PARAVIEW_SITE=$site PYTHONPATH=$site mpirun --oversubscribe -np "$np" \
  -x TERROIR_PARAVIEW_SITE -x PYTHONPATH -x TERROIR_FLOW_ITERATIONS -x OMPI_MCA_mpi_yield_when_idle -x TERROIR_TRIM \
  "$pvbatch" --symmetric "$here/ParaView/Testing/RunInParaView.py" \
  "$here/ParaView/Testing/DistributedChain.py" "$plugin" "$dem" "$run" full \
  >"$run/log.txt" 2>&1 || { echo "full chain, $np ranks, failed:"; tail -5 "$run/log.txt"; exit 1; }
t1=$(date +%s.%N)
# The serial chain and the comparison (exit 1 on any difference); /usr/bin/time for its memory.
status=0
PYTHONPATH=$standalone/lib/python3/dist-packages TERROIR_BIN_DIR=$standalone/bin \
  TERROIR_DATA_DIR=$here/Data /usr/bin/time -f "%e %M" -o "$out/serial.time" \
  /usr/bin/python3 "$here/ParaView/Testing/CompareDistributed.py" full "$np" "$dem" "$run" \
  >"$out/compare.txt" 2>&1 || status=1
tail -1 "$out/compare.txt"
/usr/bin/python3 - "$run" "$np" "$size" "$t0" "$t1" "$out/serial.time" <<'EOF'
import json, os, sys
run, np, size, t0, t1, serial = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]), sys.argv[6]
mcells = size * size / 1e6
recs = [json.load(open(os.path.join(run, 'rank%d.json' % r))) for r in range(np)]
rss = [r['max_rss_kib'] / 1024.0 for r in recs]
wall, serial_rss = (float(v) for v in open(serial).read().split('\n')[-2].split())
print('full chain %d^2 (%.1f Mcells), %d ranks: %.1f s wall (pvbatch start-up included), '
      'peak memory per rank %.0f-%.0f MiB (%.0f MiB in all, %.0f B per cell)' % (
          size, mcells, np, t1 - t0, min(rss), max(rss), sum(rss), sum(rss) * 2**20 / (size * size)))
print('serial chain and comparison (standalone build): %.1f s, peak memory %.0f MiB '
      '(%.0f B per cell)' % (wall, serial_rss / 1024.0, serial_rss * 1024.0 / (size * size)))
slowest = {}
for r in recs:
    for stage, sec in r['stage_seconds'].items():
        slowest[stage] = max(slowest.get(stage, 0.0), sec)
for stage, sec in sorted(slowest.items(), key=lambda kv: -kv[1]):
    print('  %-32s %7.2f s on the slowest rank, %6.3f s per Mcell' % (stage, sec, sec / mcells))
EOF
exit $status
