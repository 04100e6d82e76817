#!/usr/bin/env bash
# Runs DistributedChain.py on NP MPI ranks into a fresh OUT_DIR (no record of an earlier run can
# stand in for a missing one); OpenMPI on one machine, more ranks than cores allowed, as root too.
#   RunDistributed.sh MPIEXEC NP PVBATCH RUN_IN_PARAVIEW PLUGIN DEM OUT_DIR RECIPE
set -euo pipefail
mpiexec=$1 np=$2 pvbatch=$3 run=$4 plugin=$5 dem=$6 out=$7 recipe=$8
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
rm -rf "$out"
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
exec "$mpiexec" --oversubscribe -np "$np" "$pvbatch" --symmetric "$run" \
  "$here/DistributedChain.py" "$plugin" "$dem" "$out" "$recipe"
