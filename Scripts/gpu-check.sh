#!/usr/bin/env bash
# The GPU check bundle (Documentation/GPUCheck.md): terroir-gpu-check (the GPU tests and
# `terroir bench`, no GDAL) with every non-system library it needs and the tests' DEMs as .vti,
# to run on a GPU machine that has none of the build's packages.
#   Scripts/gpu-check.sh bundle [OUT.tar.xz] [--build-dir DIR] [--no-build]
#       build terroir-gpu-check, assemble terroir-gpu-check/{bin,lib,data,run.sh} and write it as
#       OUT (default: BUILD/terroir-gpu-check.tar.xz); fails over 40 MB
#   Scripts/gpu-check.sh self-test [--build-dir DIR] [--no-build] [--keep DIR]
#       make a bundle, unpack it in a temporary folder and run its run.sh --quick here (Mesa
#       llvmpipe); fails unless every test passed and every result file is there
#   run.sh OUTDIR [--sizes A,B] [--quick] [--budget SECONDS]      (inside an unpacked bundle)
#       the check itself (system, context, GPU tests, benchmarks) within the budget (default
#       330 s; --quick: 128^2 and 256^2, short stage lists, 240 s); results in OUTDIR
# The bundle's run.sh is a copy of this script. BUILD is --build-dir, else
# $TERROIR_GPU_CHECK_BUILD, else build-gpucheck in the source tree (configured when it has no
# CMakeCache.txt); --no-build uses its binaries as they are. TERROIR_JOBS: build jobs (nproc).
set -euo pipefail

self=$(readlink -f "${BASH_SOURCE[0]}")
here=$(dirname "$self")
max_bundle_bytes=40000000

die()
{
  echo "gpu-check: error: $*" >&2
  exit 1
}

# Temporary folders removed at exit (unless kept).
cleanup=()
trap 'rm -rf "${cleanup[@]}"' EXIT

# ------------------------------------------------------------------------------------------------
# Bundle
# ------------------------------------------------------------------------------------------------

# Libraries that stay behind: the C and C++ runtimes (every machine has them, and a copy would
# fight the system's own loader), and Mesa's drivers (the GPU machine brings its vendor's).
system_libraries='linux-vdso|linux-gate|ld-linux|libc\.so|libm\.so|libmvec\.so|libpthread\.so'
system_libraries+='|libdl\.so|librt\.so|libresolv\.so|libutil\.so|libanl\.so|libstdc\+\+\.so'
system_libraries+='|libgcc_s\.so|libEGL_mesa|libGLX_mesa|libglapi\.so|libgallium|libgbm\.so'
system_libraries+='|libvulkan'
system_library()
{
  [[ $1 =~ ^($system_libraries) ]]
}

# The GL loaders (GLVND) that libepoxy and the compute context dlopen: ldd cannot see them.
gl_loaders=(libEGL.so.1 libOpenGL.so.0 libGLdispatch.so.0)

# "name path" of every library `ldd FILE` resolves (its whole closure); dies on "not found".
resolved_libraries()
{
  local out
  out=$(ldd "$1") || die "ldd $1 failed"
  if grep -q "not found" <<< "$out"; then
    die "$1: libraries not found: $(grep "not found" <<< "$out" | awk '{print $1}' | tr '\n' ' ')"
  fi
  awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' <<< "$out"
}

system_path_of()
{
  /sbin/ldconfig -p | awk -v n="$1" '$1 == n && /x86-64/ {print $NF; exit}'
}

build_tree()
{
  local build=$1 root
  root=$(cd "$here/.." && pwd)
  [ -f "$root/Applications/GPUCheck.cmake" ] || die "$self is not in a Terroir source tree"
  if [ ! -f "$build/CMakeCache.txt" ]; then
    echo "gpu-check: configuring $build"
    mkdir -p "$build"
    if ! cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release \
      -DPython3_EXECUTABLE=/usr/bin/python3 -DTERROIR_WRAP_PYTHON=OFF \
      > "$build/gpu-check-configure.log" 2>&1; then
      tail -20 "$build/gpu-check-configure.log" >&2
      die "cmake configure failed (log: $build/gpu-check-configure.log)"
    fi
  fi
  echo "gpu-check: building terroir-gpu-check in $build"
  if ! cmake --build "$build" -j"${TERROIR_JOBS:-$(nproc)}" \
    --target terroir-gpu-check TerroirGPUCheckDEMToVTI > "$build/gpu-check-build.log" 2>&1; then
    tail -30 "$build/gpu-check-build.log" >&2
    die "build failed (log: $build/gpu-check-build.log)"
  fi
}

# make_bundle BUILD OUT.tar.xz: assembles the bundle in a temporary folder and writes OUT.
make_bundle()
{
  local build=$1 out=$2
  local exe=$build/bin/terroir-gpu-check tool=$build/bin/TerroirGPUCheckDEMToVTI
  if [ ! -x "$exe" ] || [ ! -x "$tool" ]; then
    die "$build/bin has no terroir-gpu-check or TerroirGPUCheckDEMToVTI: build them first"
  fi
  # shellcheck disable=SC2016
  readelf -d "$exe" | grep -q 'Library rpath: \[\$ORIGIN/../lib\]' ||
    die "$exe: DT_RPATH is not \$ORIGIN/../lib (see Applications/GPUCheck.cmake)"
  local root stage top
  root=$(cd "$here/.." && pwd)
  stage=$(mktemp -d "${TMPDIR:-/tmp}/terroir-gpu-check-bundle.XXXXXX")
  cleanup+=("$stage")
  top=$stage/terroir-gpu-check
  mkdir -p "$top/bin" "$top/lib" "$top/data"
  cp "$exe" "$top/bin/" || die "cannot copy $exe"
  cp "$self" "$top/run.sh" || die "cannot copy $self"
  chmod +x "$top/run.sh"

  # Libraries: the closure of the program, then the GL loaders and their own closure.
  local -A libs=()
  local name path list
  list=$(resolved_libraries "$exe")
  while read -r name path; do
    system_library "$name" || libs[$name]=$path
  done <<< "$list"
  local loader loader_path
  for loader in "${gl_loaders[@]}"; do
    loader_path=$(system_path_of "$loader")
    [ -n "$loader_path" ] || die "$loader is not installed (Debian: libegl1, libopengl0, libglvnd0)"
    libs[$loader]=$loader_path
    list=$(resolved_libraries "$loader_path")
    while read -r name path; do
      system_library "$name" || libs[$name]=$path
    done <<< "$list"
  done
  for name in "${!libs[@]}"; do
    cp -L "${libs[$name]}" "$top/lib/$name" || die "cannot copy ${libs[$name]}"
    chmod u+w "$top/lib/$name"
  done
  # Our libraries carry the build tree's RUNPATH, which would hide the program's DT_RPATH from
  # their own look-ups: remove every RPATH/RUNPATH in lib/.
  local with_rpath=()
  for path in "$top"/lib/*; do
    if readelf -d "$path" 2> /dev/null | grep -qE '\((RPATH|RUNPATH)\)'; then
      with_rpath+=("$path")
    fi
  done
  if [ ${#with_rpath[@]} -gt 0 ]; then
    # shellcheck disable=SC2016
    printf 'foreach(f IN LISTS FILES)\n  file(RPATH_REMOVE FILE "${f}")\nendforeach()\n' \
      > "$stage/rpath.cmake"
    cmake -DFILES="$(IFS=';'; echo "${with_rpath[*]}")" -P "$stage/rpath.cmake" > /dev/null ||
      die "cannot remove the RPATH of ${with_rpath[*]}"
  fi

  # The bundle must be closed: with no LD_LIBRARY_PATH, every library but the system's resolves
  # inside it (the program's DT_RPATH), and so do the loaders' dependencies.
  local check
  check=$(env -u LD_LIBRARY_PATH ldd "$top/bin/terroir-gpu-check") || die "ldd of the bundle failed"
  while read -r name path; do
    system_library "$name" || [[ $(readlink -f "$path") == "$top/lib/"* ]] ||
      die "bundle not closed: $name resolves to $path"
  done < <(awk '$2 == "=>" {print $1, $3}' <<< "$check")
  for loader in "${gl_loaders[@]}"; do
    list=$(resolved_libraries "$top/lib/$loader")
    while read -r name path; do
      system_library "$name" || [ -e "$top/lib/$name" ] || die "bundle lacks $name ($loader's)"
    done <<< "$list"
  done

  # The DEMs the GPU tests read (DataFile("...") in Testing/GPU), as .vti with the real reader.
  local rel
  while read -r rel; do
    [ -n "$rel" ] || continue
    mkdir -p "$top/data/$(dirname "$rel")"
    case "$rel" in
      *.tif | *.tiff | *.img | *.ter | *.asc | *.vrt)
        "$tool" "$root/Data/$rel" "$top/data/${rel%.*}.vti" > "$stage/convert.log" 2>&1 ||
          { cat "$stage/convert.log" >&2; die "cannot convert Data/$rel to .vti"; }
        sed 's/^/gpu-check: /' "$stage/convert.log" | sed "s|$top/||"
        ;;
      *) cp "$root/Data/$rel" "$top/data/$rel" ;;
    esac
  done < <(grep -ohE 'DataFile\("[^"]+"\)' "$root"/Testing/GPU/*.cxx |
    sed -E 's/DataFile\("(.*)"\)/\1/' | sort -u)

  tar -C "$stage" -cf - terroir-gpu-check | xz -9 -T0 > "$out.part" || die "cannot write $out"
  mv "$out.part" "$out" || die "cannot write $out"
  local bytes unpacked
  bytes=$(stat -c %s "$out")
  unpacked=$(du -sb "$top" | cut -f1)
  echo "gpu-check: libraries (${#libs[@]}):"
  stat -c '%s %n' "$top"/lib/* | sort -rn |
    awk '{n = split($2, p, "/"); printf "  %-44s %6.1f MB\n", p[n], $1 / 1e6}'
  awk -v o="$out" -v b="$bytes" -v u="$unpacked" \
    'BEGIN {printf "gpu-check: %s: %.1f MB compressed, %.1f MB unpacked\n", o, b / 1e6, u / 1e6}'
  [ "$bytes" -le "$max_bundle_bytes" ] ||
    die "$out is $bytes bytes, over the $max_bundle_bytes-byte limit of the GPU machine's copy"
}

# ------------------------------------------------------------------------------------------------
# Run (inside an unpacked bundle)
# ------------------------------------------------------------------------------------------------

# The benchmark jobs. The first size runs every stage but k-means (repeat 2), then k-means alone
# (its GPU path has hung before: a hang must not cost the other stages' JSON). Later sizes run
# what a few minutes allow at 8192^2 (67 Mcells), repeat 1: slope, temperature, infiltration
# and humidity (the data-movement story: GPU runs of 1-5 s against ~0.2 s on 16 cores), then
# water flow and the horizon map in whatever time is left. Monthly illumination (tens of seconds
# per run on each side, and 3 GPU runs with --gpu-breakdown), instant illumination (a horizon
# map per filter) and k-means (37 features x 67 Mcells = 10 GB) do not fit.
# Each job: NAME SIZE REPEAT STAGES CAP MIN: it runs within CAP seconds and the time left after
# the MIN seconds of every later job.
stages_first=slope,temperature,horizon,instant,monthly,infiltration,humidity,floodfill,depressions
stages_first+=,waterflow
stages_large=slope,temperature,infiltration,humidity
stages_large_extra=waterflow,horizon
quick_stages=slope,temperature,infiltration,humidity
quick_extra=horizon
tests_cap=120 # seconds for all test suites together (90 at most each)

bench_jobs()
{
  local i=0 size
  for size in ${sizes//,/ }; do
    if [ $quick = 1 ]; then
      if [ $i = 0 ]; then
        echo "bench-$size $size 1 $quick_stages 90 20"
        echo "bench-$size-kmeans $size 1 kmeans 60 10"
      else
        echo "bench-$size $size 1 $quick_stages 90 10"
        echo "bench-$size-extra $size 1 $quick_extra 90 0"
      fi
    elif [ $i = 0 ]; then
      echo "bench-$size $size 2 $stages_first 120 60"
      echo "bench-$size-kmeans $size 1 kmeans 60 20"
    else
      echo "bench-$size $size 1 $stages_large 150 90"
      echo "bench-$size-extra $size 1 $stages_large_extra 240 0"
    fi
    i=$((i + 1))
  done
}

run_check()
{
  local outdir=""
  sizes=""
  quick=0
  budget=""
  while [ $# -gt 0 ]; do
    case "$1" in
      --sizes) sizes=${2:?--sizes needs A,B}; shift 2 ;;
      --quick) quick=1; shift ;;
      --budget) budget=${2:?--budget needs seconds}; shift 2 ;;
      -h | --help) sed -n '2,16p' "$self"; return 0 ;;
      -*) die "run: unknown option $1" ;;
      *) [ -z "$outdir" ] || die "run: one OUTDIR only"; outdir=$1; shift ;;
    esac
  done
  [ -n "$outdir" ] || die "usage: run.sh OUTDIR [--sizes A,B] [--quick] [--budget SECONDS]"
  [[ -z $sizes || $sizes =~ ^[0-9]+(,[0-9]+)*$ ]] || die "--sizes: numbers separated by commas"
  [[ -z $budget || $budget =~ ^[0-9]+$ ]] || die "--budget: a number of seconds"
  if [ $quick = 1 ]; then
    sizes=${sizes:-128,256}
    budget=${budget:-240}
  else
    sizes=${sizes:-2048,8192}
    budget=${budget:-330}
  fi

  bundle=$here
  exe=$bundle/bin/terroir-gpu-check
  [ -x "$exe" ] || die "$bundle is not an unpacked bundle (no bin/terroir-gpu-check)"
  mkdir -p "$outdir" || die "cannot make $outdir"
  out=$(cd "$outdir" && pwd)
  rm -f "$out"/summary.txt "$out"/system.txt "$out"/tests.txt "$out"/bench.txt "$out"/bench-*.json
  start=$SECONDS
  deadline=$((start + budget))
  failures=0

  # The program's environment only (the system's tools keep theirs): the bundle's libraries
  # first, then the NVIDIA driver's folders where the machine has them.
  local path=$bundle/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} d
  for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do
    if [ -d "$d" ]; then
      path+=:$d
    fi
  done
  prog_env=(LD_LIBRARY_PATH="$path")
  export TERROIR_REQUIRE_GPU=1
  export TERROIR_DATA_DIR=$bundle/data
  tmp=$(mktemp -d "${TMPDIR:-/tmp}/terroir-gpu-check-run.XXXXXX")
  cleanup+=("$tmp")
  export TERROIR_TEMP_DIR=$tmp
  # The coverage test (TerroirDeterminismGPU) reads the source tree: the working copy when the
  # check runs from one (the device tool runs commands in the repository's root).
  if [ -z "${TERROIR_SOURCE_DIR:-}" ] && [ -f "$PWD/Compute/vtk.module" ] && [ -d "$PWD/Filters" ]
  then
    export TERROIR_SOURCE_DIR=$PWD
  fi
  # GLVND reads vendor files in /usr/share/glvnd/egl_vendor.d and /etc/glvnd/egl_vendor.d; a
  # container may keep NVIDIA's with the driver.
  if [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}${__EGL_VENDOR_LIBRARY_DIRS:-}" ] &&
    ! ls /usr/share/glvnd/egl_vendor.d/*nvidia* /etc/glvnd/egl_vendor.d/*nvidia* > /dev/null 2>&1 &&
    [ -f /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json ]; then
    export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
  fi
  trap 'note "INTERRUPTED after $((SECONDS - start)) s"; exit 130' INT TERM

  local jobs=() mins=() job
  while read -r job; do
    jobs+=("$job")
    mins+=("$(awk '{print $6}' <<< "$job")")
  done < <(bench_jobs)
  note "terroir GPU check: $(date -u '+%Y-%m-%d %H:%M:%S UTC') on $(uname -n), sizes $sizes," \
    "budget $budget s"
  system_report
  local reserve=0 m i
  for m in "${mins[@]}"; do
    reserve=$((reserve + m))
  done
  run_tests "$reserve"
  for i in "${!jobs[@]}"; do
    reserve=$((reserve - mins[i]))
    # shellcheck disable=SC2086
    bench_job $reserve ${jobs[i]}
  done
  local result=PASS
  [ $failures = 0 ] || result=FAIL
  note "RESULT: $result ($failures failed, timed-out or skipped steps) in $((SECONDS - start)) s"
  [ $failures = 0 ]
}

# note TEXT: one line of summary.txt, written as the check goes so that it survives a kill.
note()
{
  echo "$*" | tee -a "$out/summary.txt"
}

system_report()
{
  local f=$out/system.txt rc=0 context
  {
    echo "== uname, cpus, memory, os, C library"
    uname -a
    nproc
    free -g 2> /dev/null || true
    grep PRETTY_NAME /etc/os-release 2> /dev/null || true
    ldd --version 2> /dev/null | head -1 || true
    echo "== nvidia-smi"
    if command -v nvidia-smi > /dev/null; then
      timeout 30 nvidia-smi 2>&1 || true
      timeout 30 nvidia-smi --format=csv \
        --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm,power.draw 2>&1 || true
    else
      echo "(not installed)"
    fi
    echo "== EGL vendor files"
    for d in /usr/share/glvnd/egl_vendor.d /etc/glvnd/egl_vendor.d \
      /usr/local/nvidia/share/glvnd/egl_vendor.d; do
      for j in "$d"/*.json; do
        if [ -f "$j" ]; then
          echo "-- $j"
          cat "$j"
        fi
      done
    done
    echo "== environment"
    env | grep -E '^(TERROIR_|__EGL|__GLX|EGL_|MESA_|LD_LIBRARY_PATH)' | sort || true
    echo "the program's ${prog_env[0]}"
    echo "== libraries of terroir-gpu-check"
    env "${prog_env[@]}" ldd "$exe" 2>&1 || true
  } > "$f" 2>&1
  context=$(env "${prog_env[@]}" timeout -k 5 60 "$exe" context 2>&1) || rc=$?
  {
    echo "== terroir-gpu-check context (rc $rc)"
    echo "$context"
  } >> "$f"
  if command -v nvidia-smi > /dev/null; then
    note "gpu: $(timeout 30 nvidia-smi --format=csv,noheader \
      --query-gpu=name,driver_version,memory.total 2>&1 | head -1)"
  fi
  note "$(grep -E '^context:' <<< "$context" || echo "context: failed, rc $rc")"
  if [ $rc != 0 ]; then
    failures=$((failures + 1))
  fi
}

# run_tests RESERVE: one GoogleTest run per suite, each within 90 s, all within tests_cap and the
# time left after RESERVE seconds. The suites that have hung before run last.
run_tests()
{
  local f=$out/tests.txt list suites=() late=() s tests_end
  tests_end=$((SECONDS + tests_cap))
  if [ $((deadline - $1)) -lt $tests_end ]; then
    tests_end=$((deadline - $1))
  fi
  if ! list=$(env "${prog_env[@]}" timeout 60 "$exe" tests --gtest_list_tests 2>&1); then
    echo "$list" > "$f"
    note "tests: cannot list the suites"
    failures=$((failures + 1))
    return
  fi
  for s in $(grep -E '^[A-Za-z_][A-Za-z0-9_/]*\.$' <<< "$list" | tr -d .); do
    case "$s" in
      TerroirDeterminismGPU | KMeansGPU) late+=("$s") ;;
      *) suites+=("$s") ;;
    esac
  done
  : > "$f"
  local ok=0 failed=0 timedout=0 notrun=0
  for s in "${suites[@]}" "${late[@]}"; do
    local limit=$((tests_end - SECONDS)) rc=0 t0=$SECONDS counts
    if [ $limit -gt 90 ]; then
      limit=90
    fi
    if [ $limit -lt 5 ]; then
      echo "=== $s: not run (out of time)" >> "$f"
      note "tests $s: NOT RUN (out of time)"
      notrun=$((notrun + 1))
      continue
    fi
    echo "=== $s (timeout $limit s)" >> "$f"
    env "${prog_env[@]}" timeout -k 5 "$limit" "$exe" tests --gtest_filter="$s.*" \
      --gtest_color=no >> "$f" 2>&1 || rc=$?
    counts=$(sed -n "/^=== $s (timeout/,\$p" "$f" | awk '
      /^\[  PASSED  \] [0-9]+ test/ {p = $4}
      /^\[  FAILED  \] [0-9]+ test/ {x = $4}
      /^\[  SKIPPED \] [0-9]+ test/ {k = $4}
      END {printf "%d passed, %d failed, %d skipped", p, x, k}')
    echo "=== $s: rc $rc in $((SECONDS - t0)) s" >> "$f"
    case $rc in
      0)
        ok=$((ok + 1))
        note "tests $s: ok, $counts, $((SECONDS - t0)) s"
        ;;
      124 | 137)
        timedout=$((timedout + 1))
        note "tests $s: TIMED OUT after $limit s ($counts before)"
        ;;
      *)
        failed=$((failed + 1))
        note "tests $s: FAILED (rc $rc), $counts, $((SECONDS - t0)) s"
        ;;
    esac
  done
  note "tests: $((${#suites[@]} + ${#late[@]})) suites: $ok ok, $failed failed," \
    "$timedout timed out, $notrun not run"
  failures=$((failures + failed + timedout + notrun))
}

# bench_job RESERVE NAME SIZE REPEAT STAGES CAP MIN: `bench` within CAP seconds and the time left
# after RESERVE seconds; its output goes to bench.txt, its stage lines to summary.txt.
bench_job()
{
  local reserve=$1 name=$2 size=$3 repeat=$4 stages=$5 cap=$6
  local limit=$((deadline - SECONDS - reserve)) rc=0 t0=$SECONDS f=$out/bench.txt
  if [ $limit -gt "$cap" ]; then
    limit=$cap
  fi
  if [ "$limit" -lt 10 ]; then
    echo "=== $name: not run (out of time)" >> "$f"
    note "$name: NOT RUN (out of time)"
    failures=$((failures + 1))
    return
  fi
  echo "=== $name: bench --size $size --repeat $repeat --stages $stages (timeout $limit s)" >> "$f"
  env "${prog_env[@]}" timeout -k 5 "$limit" "$exe" bench --size "$size" --repeat "$repeat" \
    --backends cpu,gpu --gpu-breakdown --stages "$stages" --json "$out/$name.json" >> "$f" 2>&1 ||
    rc=$?
  echo "=== $name: rc $rc in $((SECONDS - t0)) s" >> "$f"
  case $rc in
    0) note "$name: ok, $((SECONDS - t0)) s (timeout $limit s)" ;;
    124 | 137) note "$name: TIMED OUT after $limit s (its finished stages are in bench.txt)" ;;
    *) note "$name: FAILED (rc $rc), $((SECONDS - t0)) s" ;;
  esac
  if [ $rc != 0 ]; then
    failures=$((failures + 1))
  fi
  sed -n "/^=== $name: bench/,\$p" "$f" | grep -E '^[a-z-]+ +(CPU|GPU) |GPU skipped' |
    sed 's/^/  /' | tee -a "$out/summary.txt" || true
}

# ------------------------------------------------------------------------------------------------
# Self-test
# ------------------------------------------------------------------------------------------------

self_test()
{
  local build=$1 keep=$2 t0=$SECONDS work
  work=$(mktemp -d "${TMPDIR:-/tmp}/terroir-gpu-check-self-test.XXXXXX")
  [ -n "$keep" ] || cleanup+=("$work")
  make_bundle "$build" "$work/terroir-gpu-check.tar.xz"
  echo "gpu-check: bundle made in $((SECONDS - t0)) s; unpacking and running run.sh --quick"
  mkdir -p "$work/unpacked"
  tar -C "$work/unpacked" -xJf "$work/terroir-gpu-check.tar.xz"
  local rc=0 t1=$SECONDS
  # As on the GPU machine: nothing from the build's environment, Mesa's EGL found by GLVND.
  (cd "$work" && env -u LD_LIBRARY_PATH -u TERROIR_EGL_PLATFORM -u TERROIR_DATA_DIR \
    -u TERROIR_BACKEND -u TERROIR_TEMP_DIR "$work/unpacked/terroir-gpu-check/run.sh" \
    "$work/results" --quick) || rc=$?
  echo "gpu-check: run.sh --quick: rc $rc in $((SECONDS - t1)) s"
  local f missing=()
  for f in summary.txt system.txt tests.txt bench.txt bench-128.json bench-128-kmeans.json \
    bench-256.json bench-256-extra.json; do
    [ -s "$work/results/$f" ] || missing+=("$f")
  done
  [ ${#missing[@]} = 0 ] || die "self-test: run.sh left no ${missing[*]} in $work/results"
  for f in "$work"/results/*.json; do
    /usr/bin/python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); assert d["results"]' \
      "$f" || die "self-test: $f is not a bench result"
  done
  grep -q "^RESULT: PASS" "$work/results/summary.txt" || die "self-test: run.sh did not pass"
  grep -q "^tests: .* 0 failed, 0 timed out, 0 not run" "$work/results/summary.txt" ||
    die "self-test: GPU tests failed"
  ! grep -q "FAILED" "$work/results/tests.txt" || die "self-test: tests.txt reports failures"
  grep -q "llvmpipe" "$work/results/system.txt" || die "self-test: the context was not llvmpipe"
  [ "$rc" = 0 ] || die "self-test: run.sh exited with $rc"
  [ -z "$keep" ] || { mkdir -p "$keep"; cp "$work"/results/* "$keep/"; }
  echo "gpu-check: self-test passed in $((SECONDS - t0)) s"
}

# ------------------------------------------------------------------------------------------------

main()
{
  # Stopped (ctest's timeout, Ctrl-C): still remove the temporary folders.
  trap 'exit 143' TERM
  trap 'exit 130' INT
  # Inside an unpacked bundle this script is run.sh: every argument is the check's.
  if [ -x "$here/bin/terroir-gpu-check" ] && [ -d "$here/lib" ]; then
    run_check "$@"
    return
  fi
  local mode=${1:-}
  [ $# -gt 0 ] && shift
  local build=${TERROIR_GPU_CHECK_BUILD:-$here/../build-gpucheck} nobuild=0 keep="" out=""
  while [ $# -gt 0 ]; do
    case "$1" in
      --build-dir) build=${2:?--build-dir needs a folder}; shift 2 ;;
      --no-build) nobuild=1; shift ;;
      --keep) keep=${2:?--keep needs a folder}; shift 2 ;;
      -*) die "unknown option $1" ;;
      *) [ -z "$out" ] || die "one output file only"; out=$1; shift ;;
    esac
  done
  mkdir -p "$build"
  build=$(cd "$build" && pwd)
  case "$mode" in
    bundle)
      [ $nobuild = 1 ] || build_tree "$build"
      out=${out:-$build/terroir-gpu-check.tar.xz}
      mkdir -p "$(dirname "$out")" || die "cannot make the folder of $out"
      make_bundle "$build" "$(cd "$(dirname "$out")" && pwd)/$(basename "$out")"
      ;;
    self-test)
      [ -z "$out" ] || die "self-test takes no output file"
      [ $nobuild = 1 ] || build_tree "$build"
      self_test "$build" "$keep"
      ;;
    -h | --help | help) sed -n '2,16p' "$self" ;;
    *) die "usage: gpu-check.sh bundle [OUT.tar.xz] | self-test [--build-dir DIR] [--no-build]" ;;
  esac
}

main "$@"
