#!/usr/bin/env bash
# Times the k-means core's assignment and block sums on 1024^2 cells x 37 features, K = 5 and 10,
# 1 and 2 threads (Testing/Benchmarks/KMeansCoreTiming.cxx, linked against the built core
# library; reference: scikit-learn 1.2 takes about 87 ms per Lloyd iteration on that input).
#   Testing/Benchmarks/kmeans_core.sh [BUILD_DIR] [REPS]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$here/build}
reps=${2:-20}
lib="$build/lib/libTerroirClusteringCore.a"
[ -f "$lib" ] || { echo "$lib not found: build the target TerroirClusteringCore first" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
${CXX:-g++} -O2 -std=c++17 -pthread -I"$here/Filters/Clustering/Core" \
  "$here/Testing/Benchmarks/KMeansCoreTiming.cxx" "$lib" -o "$work/timing"
"$work/timing" "$reps"
