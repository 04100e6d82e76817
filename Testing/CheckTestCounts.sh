#!/usr/bin/env bash
# Fails when fewer tests are registered under a label than the suite holds today: a missing
# interpreter, tool or module (VTK's Python, glslangValidator, xvfb, a GoogleTest executable
# that failed to build its list) must not make tests disappear unnoticed.
#   Testing/CheckTestCounts.sh CTEST BUILD_DIR [LABEL]
# With LABEL, only that label's minimum (the ParaView plugin tree holds only labels paraview and
# mpi, its distributed tests, which are paraview tests too).
# Raise a minimum when tests are added; lower one only with the reason in the commit.
set -euo pipefail
ctest=$1
build=$2
only=${3:-}
declare -A minimum=(
  [unit]=427 [pipeline]=214 [gpu]=81 [rendering]=54 [python]=20 [examples]=16 [fuzz]=5
  [stress]=2 [benchmarks]=1 [scripts]=1 [paraview]=101 [mpi]=88
)
status=0
labels=("${!minimum[@]}")
[ -n "$only" ] && labels=("$only")
for label in "${labels[@]}"; do
  # The standalone tree has no paraview or mpi tests: they live in the plugin's tree.
  [ -z "$only" ] && { [ "$label" = paraview ] || [ "$label" = mpi ]; } && continue
  count=$("$ctest" --test-dir "$build" -N -L "^${label}\$" | grep -c 'Test *#' || true)
  if [ "$count" -lt "${minimum[$label]}" ]; then
    echo "label $label: $count tests registered, expected at least ${minimum[$label]}"
    status=1
  else
    echo "label $label: $count tests (at least ${minimum[$label]})"
  fi
done
[ -n "$only" ] && exit $status
# Tests that exist only when a tool was found at configure time.
for name in ShadersCompile Python.TestGrassPeer Python.TestViewer; do
  listed=$("$ctest" --test-dir "$build" -N -R "^${name}\$")
  if ! grep -q 'Test *#' <<<"$listed"; then
    echo "test $name is not registered (its tool was not found when CMake ran)"
    status=1
  fi
done
exit $status
