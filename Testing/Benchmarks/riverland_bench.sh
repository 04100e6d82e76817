#!/usr/bin/env bash
# Times RiverLand (Jensen 2011; IO/Core/RiverLand.h): the medial-axis pruning and the whole
# generator at 350^2 and 700^2 (Jensen's Figure 18: pruning 1.205 s and 3.844 s), 2048^2 and
# 8192^2 (Testing/Benchmarks/RiverLandTiming.cxx, linked against the built core library; best of
# REPS runs, 1 and 2 threads, an island and a dense river network).
#   Testing/Benchmarks/riverland_bench.sh [BUILD_DIR] [REPS] [SIZES...]
# Defaults: build, 3 repetitions, 350 700 2048 8192 (8192^2 peaks at about 6 GB of memory and takes about 4 minutes).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$here/build}
reps=${2:-3}
shift 2 2>/dev/null || shift $#
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(350 700 2048 8192)
lib="$build/lib/libTerroirIOCore.a"
[ -f "$lib" ] || { echo "$lib not found: build the target TerroirIOCore first" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
${CXX:-g++} -O2 -std=c++17 -pthread -I"$here/IO/Core" \
  "$here/Testing/Benchmarks/RiverLandTiming.cxx" "$lib" -o "$work/timing"
"$work/timing" "$reps" "${sizes[@]}"
