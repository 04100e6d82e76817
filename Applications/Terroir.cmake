# The `terroir` program, and its overlay module (loaded with dlopen by `terroir run`, so that
# the other commands do not pay for loading VTK's rendering libraries).
find_path(CLI11_INCLUDE_DIR CLI/CLI.hpp REQUIRED)
find_package(nlohmann_json 3 REQUIRED)

# The command-line parser alone (CLI11, no VTK): unit tests and the fuzz harness link it too.
# It checks dates with the terrain core's calendar (TerroirTerrainCore, plain C++, no VTK).
# Each command's options live beside its code, in Commands/<Name>Options.cxx (TerroirCommandOptions.h).
file(GLOB _terroir_option_files CONFIGURE_DEPENDS
  "${CMAKE_CURRENT_SOURCE_DIR}/Commands/*Options.cxx"
  "${CMAKE_CURRENT_SOURCE_DIR}/Commands/TerroirCommandOptions.h")
add_library(TerroirCommandLine STATIC TerroirCommandLine.cxx TerroirCommandLine.h
  TerroirViewerScript.cxx TerroirViewerScript.h ${_terroir_option_files})
target_include_directories(TerroirCommandLine PUBLIC "${CMAKE_CURRENT_SOURCE_DIR}"
  PRIVATE "${CLI11_INCLUDE_DIR}" "${CMAKE_CURRENT_SOURCE_DIR}/Commands")
# `generate riverland` checks its --params with RiverLand's core (TerroirIOCore, no VTK).
target_link_libraries(TerroirCommandLine PRIVATE TerroirTerrainCore TerroirIOCore)
target_compile_features(TerroirCommandLine PUBLIC cxx_std_17)
target_compile_options(TerroirCommandLine PRIVATE -Wall -Wextra)

# The commands (Commands/: one file per command, the registry TerroirCommands.h) as a static
# library, so that the pipeline tests can check the registry against the parser's commands.
file(GLOB _terroir_command_files CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/Commands/*.cxx"
  "${CMAKE_CURRENT_SOURCE_DIR}/Commands/*.h")
list(FILTER _terroir_command_files EXCLUDE REGEX "Options\\.(cxx|h)$")
add_library(TerroirCommands STATIC ${_terroir_command_files} TerroirApp.cxx TerroirAppCore.cxx
  TerroirApp.h TerroirBench.cxx TerroirBench.h TerroirBenchPrivate.h TerroirBenchProbes.cxx
  TerroirBenchStages.cxx TerroirOverlayPlugin.h)
target_include_directories(TerroirCommands PUBLIC "${CMAKE_CURRENT_SOURCE_DIR}"
  "${CMAKE_CURRENT_SOURCE_DIR}/Commands")
target_compile_definitions(TerroirCommands PRIVATE
  "TERROIR_DATA_DIR=\"${PROJECT_SOURCE_DIR}/Data\""
  "TERROIR_INSTALL_LIBDIR=\"${CMAKE_INSTALL_LIBDIR}\"")
target_compile_options(TerroirCommands PRIVATE -Wall -Wextra)

add_executable(terroir terroir.cxx)
target_compile_options(terroir PRIVATE -Wall -Wextra)
set(_terroir_app_modules Terroir::Common Terroir::Compute Terroir::IO Terroir::FiltersBase
  Terroir::FiltersTerrain
  Terroir::FiltersHydrology Terroir::FiltersClustering
  VTK::CommonCore VTK::CommonDataModel VTK::CommonExecutionModel VTK::CommonMisc VTK::IOXML)
target_link_libraries(TerroirCommands PUBLIC TerroirCommandLine ${_terroir_app_modules}
  TerroirTerrainCore TerroirIOCore TerroirHydrologyCore nlohmann_json::nlohmann_json ${CMAKE_DL_LIBS})
target_link_libraries(terroir PRIVATE TerroirCommands)
vtk_module_autoinit(TARGETS terroir MODULES ${_terroir_app_modules})
install(TARGETS terroir RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")

add_library(terroir-overlay MODULE TerroirOverlayPlugin.cxx TerroirOverlayPlugin.h)
set_target_properties(terroir-overlay PROPERTIES PREFIX "" OUTPUT_NAME "terroir-overlay"
  CXX_VISIBILITY_PRESET hidden)
target_compile_options(terroir-overlay PRIVATE -Wall -Wextra)
set(_terroir_overlay_modules Terroir::Rendering VTK::CommonCore VTK::CommonDataModel
  VTK::RenderingOpenGL2 VTK::RenderingFreeType VTK::InteractionStyle)
target_link_libraries(terroir-overlay PRIVATE ${_terroir_overlay_modules})
vtk_module_autoinit(TARGETS terroir-overlay MODULES ${_terroir_overlay_modules})
add_dependencies(terroir terroir-overlay)
install(TARGETS terroir-overlay LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}")

# `terroir view`: the window-free model (unit-tested by Testing/Pipeline/TestViewerSession.cxx)
# and the window module, loaded with dlopen like the overlay module.
add_library(TerroirViewerSession STATIC TerroirViewerSession.cxx TerroirViewerSession.h
  TerroirViewerSessionEdits.cxx TerroirViewerSessionErosion.cxx TerroirViewerSessionOverlays.cxx
  TerroirViewerSessionWorker.cxx
  TerroirViewerSessionPrivate.h)
set_target_properties(TerroirViewerSession PROPERTIES POSITION_INDEPENDENT_CODE ON)
target_include_directories(TerroirViewerSession PUBLIC "${CMAKE_CURRENT_SOURCE_DIR}")
target_compile_options(TerroirViewerSession PRIVATE -Wall -Wextra)
find_package(Threads REQUIRED)
target_link_libraries(TerroirViewerSession PUBLIC TerroirCommandLine VTK::CommonCore
  VTK::CommonDataModel VTK::CommonExecutionModel Terroir::Common Terroir::FiltersBase
  Terroir::FiltersTerrain
  Terroir::FiltersHydrology Terroir::FiltersClustering
  PRIVATE Terroir::IO TerroirTerrainCore Threads::Threads)
set_target_properties(TerroirCommandLine PROPERTIES POSITION_INDEPENDENT_CODE ON)

add_library(terroir-viewer MODULE TerroirViewerWindow.cxx TerroirViewerWindowCamera.cxx
  TerroirViewerWindowOverlay.cxx TerroirViewerWindowScript.cxx TerroirViewerWindowTools.cxx
  TerroirViewerWindowCards.cxx TerroirViewerWindowErosion.cxx
  TerroirViewerWindowPrivate.h TerroirViewerPlugin.h)
set_target_properties(terroir-viewer PROPERTIES PREFIX "" OUTPUT_NAME "terroir-viewer"
  CXX_VISIBILITY_PRESET hidden)
target_compile_options(terroir-viewer PRIVATE -Wall -Wextra)
set(_terroir_viewer_modules Terroir::Rendering Terroir::Common VTK::CommonCore
  VTK::CommonDataModel VTK::RenderingCore VTK::RenderingOpenGL2 VTK::RenderingFreeType
  VTK::RenderingAnnotation VTK::InteractionStyle VTK::InteractionWidgets VTK::IOImage)
target_link_libraries(terroir-viewer PRIVATE TerroirViewerSession ${_terroir_viewer_modules})
vtk_module_autoinit(TARGETS terroir-viewer MODULES ${_terroir_viewer_modules})
add_dependencies(terroir terroir-viewer)
install(TARGETS terroir-viewer LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}")
