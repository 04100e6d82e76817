# GPUCheck.BundleRunsOnLlvmpipe (label gpu): Scripts/gpu-check.sh self-test on this build tree's
# terroir-gpu-check (Applications/GPUCheck.cmake, built with `all`): it makes the GPU check
# bundle, unpacks it in a temporary folder and runs its run.sh --quick here, on Mesa llvmpipe,
# then checks the result files and that every GPU test passed (Documentation/GPUCheck.md).
# About a minute on 2 cores. Not in sanitizer or fuzzing builds, whose runtimes do not travel.
if(TARGET terroir-gpu-check AND TARGET TerroirGPUCheckDEMToVTI AND NOT TERROIR_SANITIZE
    AND NOT TERROIR_FUZZ)
  add_test(NAME GPUCheck.BundleRunsOnLlvmpipe
    COMMAND bash "${PROJECT_SOURCE_DIR}/Scripts/gpu-check.sh" self-test
      --build-dir "${PROJECT_BINARY_DIR}" --no-build)
  set_tests_properties(GPUCheck.BundleRunsOnLlvmpipe PROPERTIES
    LABELS gpu
    TIMEOUT 280
    PROCESSORS 2
    ENVIRONMENT "TMPDIR=${PROJECT_BINARY_DIR}/Testing/Temporary")
endif()
