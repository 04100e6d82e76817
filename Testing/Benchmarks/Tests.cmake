# The benchmarks at a tiny size (Testing/Benchmarks/smoke.sh): they run in every CI build so
# they cannot rot; the timings are not checked (speed is measured, never asserted).
add_test(NAME BenchmarksSmoke
  COMMAND bash "${CMAKE_CURRENT_LIST_DIR}/smoke.sh" "${PROJECT_BINARY_DIR}"
          "${PROJECT_BINARY_DIR}/Testing/Temporary/benchmarks")
set_tests_properties(BenchmarksSmoke PROPERTIES LABELS benchmarks TIMEOUT 600)
