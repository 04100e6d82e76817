#!/usr/bin/env bash
# Terroir set-up on a fresh Debian 12 machine, then one job:
#   Scripts/setup.sh run [terroir run options...]   install, build, run the pipeline on the bundled DEM
#   Scripts/setup.sh test [ctest options...]        install, build, run the whole test suite
#   Scripts/setup.sh build                          install and build only
#   Scripts/setup.sh sanitize [ctest options...]    also build a second tree with clang,
#                                                   AddressSanitizer, UndefinedBehaviorSanitizer
#                                                   and libFuzzer, and run the unit, pipeline and
#                                                   GPU tests there (any report fails)
#   Scripts/setup.sh configure-sanitize             configure that tree only (Testing/Fuzz/run.sh)
#   Scripts/setup.sh paraview [ctest options...]    also build the ParaView plugin (a second tree
#                                                   against Debian's ParaView 5.11) and run its
#                                                   tests (label paraview); `test` does it too
# Idempotent: packages already present are not reinstalled; the builds are incremental.
# Environment: TERROIR_BUILD_DIR (default ./build), TERROIR_SANITIZE_BUILD_DIR (default
# ./build-asan), TERROIR_PARAVIEW_BUILD_DIR (default ./build-paraview), TERROIR_JOBS (default 2).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TERROIR_BUILD_DIR:-$here/build}
sanitize_build=${TERROIR_SANITIZE_BUILD_DIR:-$here/build-asan}
paraview_build=${TERROIR_PARAVIEW_BUILD_DIR:-$here/build-paraview}
jobs=${TERROIR_JOBS:-2}
mode=${1:-build}
[ $# -gt 0 ] && shift

# Debian 12 packages Terroir needs to build, test and run (grass-core and saga: peer tools the
# tests compare with; GRASS r.sunmask, r.horizon and r.watershed, SAGA's flow accumulation).
packages=(
  build-essential cmake pkg-config git
  libvtk9-dev python3-vtk9 python3-numpy python3-scipy python3-sklearn
  libgdal-dev gdal-bin python3-gdal
  libgeographiclib-dev
  libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libx11-dev
  libgtest-dev libcli11-dev nlohmann-json3-dev
  glslang-tools xvfb xauth time
  clang libclang-rt-14-dev llvm
  grass-core saga
  paraview paraview-dev libopenmpi-dev openmpi-bin
)

install_packages() {
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    echo "setup: all ${#packages[@]} Debian packages present"
    return
  fi
  echo "setup: installing ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

build_terroir() {
  if [ ! -f "$build/CMakeCache.txt" ]; then
    cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3
  fi
  cmake --build "$build" -j "$jobs"
}

# The second tree: clang with sanitizers on every target, and libFuzzer coverage (the harnesses
# of Testing/Fuzz link libFuzzer there). No Python wrapping: VTK's Python is not instrumented.
configure_sanitize() {
  if ! grep -q "TERROIR_FUZZ:BOOL=ON" "$sanitize_build/CMakeCache.txt" 2>/dev/null; then
    CC=clang CXX=clang++ cmake -S "$here" -B "$sanitize_build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DTERROIR_SANITIZE=address,undefined -DTERROIR_FUZZ=ON -DTERROIR_WRAP_PYTHON=OFF \
      -DPython3_EXECUTABLE=/usr/bin/python3
  else
    cmake -S "$here" -B "$sanitize_build" >/dev/null
  fi
}

# The ParaView plugin tree (Documentation/ParaView.md). python3-paraview (pvpython, ParaView's
# Python modules) conflicts with python3-vtk9 and is unpacked into the tree's prefix instead of
# installed (ParaView/MakePrefix.sh); the plugin's tests compare with the standalone tree.
build_paraview() {
  local prefix=$paraview_build/paraview-prefix
  if [ ! -x "$prefix/usr/bin/pvpython" ]; then
    mkdir -p "$paraview_build/deb"
    (cd "$paraview_build/deb" && apt-get download python3-paraview)
    bash "$here/ParaView/MakePrefix.sh" "$prefix" "$(ls "$paraview_build"/deb/python3-paraview_*.deb)"
  fi
  if [ ! -f "$paraview_build/CMakeCache.txt" ]; then
    cmake -S "$here" -B "$paraview_build" -DCMAKE_BUILD_TYPE=Release -DTERROIR_PARAVIEW_PLUGIN=ON \
      -DTERROIR_STANDALONE_BUILD="$build" -DPython3_EXECUTABLE=/usr/bin/python3
  fi
  cmake --build "$paraview_build" -j "$jobs"
}

# VTK 9.1 renders through X only: PNG export and image tests need a display.
with_display() {
  if [ -n "${DISPLAY:-}" ]; then "$@"; else xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$@"; fi
}

install_packages
case "$mode" in
  configure-sanitize) configure_sanitize; exit 0 ;;
  sanitize) ;;
  paraview) build_terroir; build_paraview ;;
  test) build_terroir; build_paraview ;;
  *) build_terroir ;;
esac
case "$mode" in
  build) ;;
  # The set-up's own job replaces its own earlier results (terroir itself refuses to overwrite
  # files unless asked), so running this command twice gives the same outcome.
  run) with_display "$build/bin/terroir" run --overwrite "$@" ;;
  test)
    # The GPU path is exercised for real on llvmpipe: a missing compute context is a failure;
    # so is a missing peer program (gdaldem, ogr2ogr: the tests would otherwise skip).
    export TERROIR_REQUIRE_GPU=${TERROIR_REQUIRE_GPU:-1}
    export TERROIR_REQUIRE_PEERS=${TERROIR_REQUIRE_PEERS:-1}
    with_display ctest --test-dir "$build" --output-on-failure -j "$jobs" "$@"
    with_display ctest --test-dir "$paraview_build" --output-on-failure -j "$jobs" ;;
  paraview) with_display ctest --test-dir "$paraview_build" --output-on-failure -j "$jobs" "$@" ;;
  sanitize)
    configure_sanitize
    cmake --build "$sanitize_build" -j "$jobs"
    export TERROIR_REQUIRE_GPU=${TERROIR_REQUIRE_GPU:-1}
    export TERROIR_REQUIRE_PEERS=${TERROIR_REQUIRE_PEERS:-1}
    # Each test runs with ASAN_OPTIONS/UBSAN_OPTIONS set by Testing/CMakeLists.txt: a leak, a
    # memory error or undefined behaviour aborts the test, so the run fails.
    with_display ctest --test-dir "$sanitize_build" --output-on-failure -j "$jobs" \
      -L 'unit|pipeline|gpu' "$@" ;;
  *) echo "usage: Scripts/setup.sh run|test|build|sanitize|configure-sanitize|paraview [args...]" >&2
     exit 2 ;;
esac
