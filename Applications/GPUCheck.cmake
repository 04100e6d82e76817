# terroir-gpu-check, the GDAL-free program of the GPU check bundle (Scripts/gpu-check.sh,
# Documentation/GPUCheck.md): `terroir bench` and the GPU test suite (Testing/GPU/Test*.cxx, with
# Testing/Common) in one executable that links neither Terroir::IO nor GDAL. The tests read their
# DEMs from .vti copies through Testing/Common/GPUCheck/vtkTerroirDEMReader.h, a stand-in found
# before the real reader's header, and their folders at run time (TerroirGPUCheckPaths.h,
# force-included). TerroirGPUCheckDEMToVTI writes those copies with the real reader (GDAL), at
# bundle time, and checks that they read back identical.
option(TERROIR_GPU_CHECK "Build terroir-gpu-check, the program of the GPU check bundle" ON)
set(_gpu_check_ready ${TERROIR_GPU_CHECK})
foreach(_t TerroirCommandLine Terroir::Common Terroir::Compute Terroir::IO Terroir::FiltersTerrain
    Terroir::FiltersHydrology Terroir::FiltersClustering)
  if(NOT TARGET ${_t})
    set(_gpu_check_ready OFF)
  endif()
endforeach()
if(_gpu_check_ready)
  find_package(GTest QUIET)
  if(NOT GTest_FOUND)
    message(STATUS "terroir-gpu-check skipped: GoogleTest not found")
    set(_gpu_check_ready OFF)
  endif()
endif()

if(_gpu_check_ready)
  set(_gpu_check_common "${PROJECT_SOURCE_DIR}/Testing/Common")
  set(_gpu_check_vti "${_gpu_check_common}/GPUCheck")
  file(GLOB _gpu_check_tests CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/Testing/GPU/Test*.cxx")
  file(GLOB _gpu_check_helpers CONFIGURE_DEPENDS "${_gpu_check_common}/*.cxx")

  set(_gpu_check_modules Terroir::Common Terroir::Compute Terroir::FiltersBase
    Terroir::FiltersTerrain
    Terroir::FiltersHydrology Terroir::FiltersClustering
    VTK::CommonCore VTK::CommonDataModel VTK::CommonExecutionModel VTK::CommonMisc
    VTK::CommonSystem VTK::ImagingCore VTK::IOXML)
  set(_gpu_check_core_libs TerroirCommonCore TerroirTerrainCore TerroirHydrologyCore
    TerroirClusteringCore TerroirIOCore)

  # The GPU tests and their helpers, as the TerroirGPUTests executable builds them, but with the
  # .vti reader and the run-time folders.
  add_library(TerroirGPUCheckTests OBJECT ${_gpu_check_tests} ${_gpu_check_helpers}
    "${_gpu_check_vti}/TerroirTestDataVTI.cxx")
  target_include_directories(TerroirGPUCheckTests BEFORE PRIVATE "${_gpu_check_vti}")
  target_include_directories(TerroirGPUCheckTests PRIVATE "${_gpu_check_common}")
  target_compile_options(TerroirGPUCheckTests PRIVATE -Wall -Wextra
    "SHELL:-include \"${_gpu_check_vti}/TerroirGPUCheckPaths.h\"")
  set_source_files_properties("${_gpu_check_vti}/TerroirTestDataVTI.cxx" PROPERTIES
    COMPILE_DEFINITIONS "TERROIR_GPU_CHECK_CONFIGURED_SOURCE_DIR=\"${PROJECT_SOURCE_DIR}\"")
  target_link_libraries(TerroirGPUCheckTests PRIVATE ${_gpu_check_modules}
    ${_gpu_check_core_libs} GTest::gtest)

  add_executable(terroir-gpu-check TerroirGPUCheck.cxx TerroirBench.cxx TerroirBench.h
    TerroirBenchPrivate.h TerroirBenchProbes.cxx TerroirBenchStages.cxx
    TerroirAppCore.cxx TerroirApp.h)
  target_compile_options(terroir-gpu-check PRIVATE -Wall -Wextra)
  target_link_libraries(terroir-gpu-check PRIVATE TerroirGPUCheckTests TerroirCommandLine
    ${_gpu_check_modules} ${_gpu_check_core_libs} nlohmann_json::nlohmann_json GTest::gtest
    Threads::Threads)
  # Relocatable: bin/ finds lib/ through DT_RPATH $ORIGIN/../lib (which, unlike DT_RUNPATH, also
  # serves the libraries' own look-ups and dlopen), in the build tree and in the bundle alike.
  # With BUILD_RPATH_USE_ORIGIN, CMake's build RPATH is exactly that (no absolute build-tree
  # path, so that a library missing from the bundle shows); Scripts/gpu-check.sh checks it.
  set_target_properties(terroir-gpu-check PROPERTIES BUILD_RPATH_USE_ORIGIN ON)
  target_link_options(terroir-gpu-check PRIVATE "LINKER:--disable-new-dtags")

  # Build-time tool of Scripts/gpu-check.sh (not bundled): the tests' DEMs as .vti.
  add_executable(TerroirGPUCheckDEMToVTI "${_gpu_check_vti}/TerroirGPUCheckDEMToVTI.cxx"
    "${_gpu_check_common}/TerroirFilterTestUtilities.cxx")
  target_include_directories(TerroirGPUCheckDEMToVTI PRIVATE "${_gpu_check_common}")
  target_compile_definitions(TerroirGPUCheckDEMToVTI PRIVATE
    "TERROIR_DATA_DIR=\"${PROJECT_SOURCE_DIR}/Data\""
    "TERROIR_TEMP_DIR=\"${PROJECT_BINARY_DIR}/Testing/Temporary\""
    "TERROIR_SOURCE_DIR=\"${PROJECT_SOURCE_DIR}\"")
  target_compile_options(TerroirGPUCheckDEMToVTI PRIVATE -Wall -Wextra)
  target_link_libraries(TerroirGPUCheckDEMToVTI PRIVATE Terroir::IO ${_gpu_check_modules})

  vtk_module_autoinit(TARGETS TerroirGPUCheckTests terroir-gpu-check TerroirGPUCheckDEMToVTI
    MODULES ${_gpu_check_modules})
else()
  message(STATUS "terroir-gpu-check skipped: TERROIR_GPU_CHECK is off or a module is missing")
endif()
