#!/usr/bin/env bash
# Strong and weak scaling of the distributed chain (issue 25; Documentation/Scaling.md): the
# ParaView chain of DistributedChain.py under `mpirun --oversubscribe -np N pvbatch --symmetric`
# at N = 1, 2, 4, on
#   strong: the bundled Sagehen DEM (786 x 720) and a SIZE^2 fractal DEM (default 2048);
#   weak:   fractal DEMs of about CELLS_PER_RANK cells per rank (default 1024^2: 1024^2, 1448^2,
#           2048^2 at 1, 2, 4 ranks);
# for three recipes: `zones` (reader, slope, temperature, infiltration, soil humidity, k-means),
# `flow` (reader, water flow: Pulse, FLOW_ITERATIONS iterations, default 100, the auto-stop
# off so that every size runs the same count) and `lakes` (reader, flood fill FillDepressions:
# Barnes 2016's parallel Priority-Flood). TERROIR_SCALING_RECIPES picks recipes (default all
# three), TERROIR_SCALING_WEAK the weak runs' side per rank (default 1024; the smoke test in
# the ParaView tree runs tiny sizes: ParaView.ScalingBenchmarkSmoke). Each rank records the seconds each stage's
# RequestData took (StartEvent to EndEvent), its output arrays and its peak resident memory;
# the table gives, per run, the slowest rank's seconds per stage, the pipeline's wall time,
# speed-up and efficiency against 1 rank, and seconds per million cells of the slowest rank.
#   Testing/Benchmarks/scaling_mpi.sh [PARAVIEW_BUILD] [OUT_DIR] [SIZE] [FLOW_ITERATIONS]
# Needs the ParaView build (build-paraview: its plugin and paraview-prefix) and the standalone
# build's `terroir` (TERROIR_STANDALONE_BUILD, default build/) for `terroir fractal`.
# On a machine with fewer cores than ranks (the 2-core development machine) the ranks share
# cores: the numbers then check the method (what each rank reads, holds and sends), not speed.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
pvbuild=${1:-$here/build-paraview}
out=${2:-$(mktemp -d)}
size=${3:-2048}
iterations=${4:-100}
standalone=${TERROIR_STANDALONE_BUILD:-$here/build}
pvbatch=$pvbuild/paraview-prefix/usr/bin/pvbatch
plugin=$pvbuild/lib/paraview-5.11/plugins/Terroir/Terroir.so
terroir=$standalone/bin/terroir
for f in "$pvbatch" "$plugin" "$terroir"; do
  [ -e "$f" ] || { echo "$f not found: build the ParaView and standalone trees first" >&2; exit 1; }
done
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export TERROIR_FLOW_ITERATIONS=$iterations
# One core's worth per rank: one vtkSMPTools thread (VTK_SMP_MAX_THREADS), and a rank waiting in
# MPI gives its core back (OpenMPI busy-polls otherwise, which on an oversubscribed machine takes
# the core from the rank it waits for). TERROIR_SCALING_THREADS overrides the thread count.
export VTK_SMP_MAX_THREADS=${TERROIR_SCALING_THREADS:-1} OMPI_MCA_mpi_yield_when_idle=1
# ParaView's own Python modules first (RunInParaView.py; as the ParaView tests set them).
site=$pvbuild/paraview-prefix/usr/lib/python3/dist-packages
export TERROIR_PARAVIEW_SITE=$site PYTHONPATH=$site

dem_of() { # dem_of NAME -> path (made once)
  case $1 in
    sagehen) echo "$here/Data/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif" ;;
    fractal*)
      local n=${1#fractal}
      [ -e "$out/$1.tif" ] || "$terroir" fractal "$out/$1.tif" --size "$n" --seed 7 >/dev/null
      echo "$out/$1.tif" ;;
  esac
}

run() { # run KIND DEM NP RECIPE
  local kind=$1 dem=$2 np=$3 recipe=$4
  local dir=$out/$kind-$dem-np$np-$recipe
  rm -rf "$dir"
  mkdir -p "$dir"
  local t0=$(date +%s.%N)
  mpirun --oversubscribe -np "$np" -x TERROIR_PARAVIEW_SITE -x PYTHONPATH -x TERROIR_FLOW_ITERATIONS \
    -x VTK_SMP_MAX_THREADS -x OMPI_MCA_mpi_yield_when_idle \
    "$pvbatch" --symmetric "$here/ParaView/Testing/RunInParaView.py" \
    "$here/ParaView/Testing/DistributedChain.py" "$plugin" "$(dem_of "$dem")" "$dir" "$recipe" \
    >"$dir/log.txt" 2>&1 || { echo "$kind $dem np$np $recipe failed:"; tail -5 "$dir/log.txt"; return 1; }
  local t1=$(date +%s.%N)
  echo "$kind $dem $np $recipe $(awk -v a="$t0" -v b="$t1" 'BEGIN{print b - a}')" >>"$out/runs.txt"
}

rm -f "$out/runs.txt"
echo "scaling benchmark: $(nproc) cores, ranks oversubscribed where more than cores; out $out"
weak=${TERROIR_SCALING_WEAK:-1024}
weak2=$(/usr/bin/python3 -c "print(round($weak * 2 ** 0.5))")
for recipe in ${TERROIR_SCALING_RECIPES:-zones flow lakes}; do
  for dem in sagehen "fractal$size"; do
    for np in 1 2 4; do run strong "$dem" "$np" "$recipe"; done
  done
  # Weak: about weak^2 cells per rank.
  run weak "fractal$weak" 1 "$recipe"
  run weak "fractal$weak2" 2 "$recipe"
  run weak "fractal$((2 * weak))" 4 "$recipe"
done
/usr/bin/python3 "$here/Testing/Benchmarks/scaling_summary.py" "$out"
