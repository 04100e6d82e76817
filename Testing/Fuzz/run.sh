#!/usr/bin/env bash
# Fuzzes every harness of Testing/Fuzz with libFuzzer for MINUTES each (default 1; decimals
# allowed, e.g. 0.5), one after the other, in the sanitizer build tree (clang, AddressSanitizer
# + UndefinedBehaviorSanitizer + libFuzzer; configured and built here when missing):
#
#   bash Testing/Fuzz/run.sh [MINUTES] [HARNESS...]      e.g.  bash Testing/Fuzz/run.sh 30 DEMReader
#
# Each harness starts from its seeds (corpus/<Name>/) and saved crash inputs (regressions/<Name>/)
# and grows a working corpus in $TERROIR_SANITIZE_BUILD_DIR/Testing/Fuzz/<Name>/corpus (kept
# between runs, never written into the repository). A crash, leak, sanitizer report or timeout is
# saved under .../<Name>/artifacts/ and makes this script fail: reproduce it with
#   build-asan/bin/Fuzz<Name> <artifact>
# fix it, and copy the artifact into Testing/Fuzz/regressions/<Name>/ (CTest replays that folder)
# with a regression test next to the code's other tests.
# Environment: TERROIR_SANITIZE_BUILD_DIR (default ./build-asan), TERROIR_JOBS (default 2).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
build=${TERROIR_SANITIZE_BUILD_DIR:-$repo/build-asan}
jobs=${TERROIR_JOBS:-2}
minutes=${1:-1}
[ $# -gt 0 ] && shift
harnesses=("$@")
[ ${#harnesses[@]} -eq 0 ] && harnesses=(Terragen ClimateTable CommandLine DEMReader VectorRasterizer)
seconds=$(awk -v m="$minutes" 'BEGIN { s = int(m * 60 + 0.5); if (s < 1) s = 1; print s }')

declare -A max_len=([Terragen]=16384 [ClimateTable]=4096 [CommandLine]=512 [DEMReader]=17000 [VectorRasterizer]=8192)

bash "$repo/Scripts/setup.sh" configure-sanitize >/dev/null
cmake --build "$build" -j "$jobs" --target "${harnesses[@]/#/Fuzz}" >/dev/null

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:check_initialization_order=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# Leaks inside GDAL and PROJ themselves (lsan-third-party.supp says which and why).
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$here/lsan-third-party.supp:print_suppressions=0}
failed=0
printf '%-17s %8s %12s %9s %10s %s\n' harness seconds executions exec/s "new units" result
for name in "${harnesses[@]}"; do
  work="$build/Testing/Fuzz/$name"
  mkdir -p "$work/corpus" "$work/artifacts"
  inputs=("$work/corpus" "$here/corpus/$name")
  [ -d "$here/regressions/$name" ] && inputs+=("$here/regressions/$name")
  log="$work/last-run.log"
  status=0
  "$build/bin/Fuzz$name" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len="${max_len[$name]:-4096}" -print_final_stats=1 -artifact_prefix="$work/artifacts/" \
    "${inputs[@]}" >"$log" 2>&1 || status=$?
  stat() { awk -v k="stat::$1:" '$1 == k { print $2 }' "$log"; }
  found=$(ls "$work/artifacts" 2>/dev/null | wc -l)
  result="clean"
  if [ "$status" -ne 0 ] || [ "$found" -ne 0 ]; then
    result="FOUND: $(ls "$work/artifacts" | tr '\n' ' ')(log: $log)"
    failed=1
  fi
  printf '%-17s %8s %12s %9s %10s %s\n' "$name" "$seconds" "$(stat number_of_executed_units)" \
    "$(stat average_exec_per_sec)" "$(stat new_units_added)" "$result"
done
exit $failed
