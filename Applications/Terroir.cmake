# The `terroir` program.
find_path(CLI11_INCLUDE_DIR CLI/CLI.hpp REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
add_executable(terroir terroir.cxx TerroirApp.cxx TerroirApp.h)
target_include_directories(terroir PRIVATE "${CLI11_INCLUDE_DIR}")
target_compile_definitions(terroir PRIVATE "TERROIR_DATA_DIR=\"${PROJECT_SOURCE_DIR}/Data\"")
target_compile_options(terroir PRIVATE -Wall -Wextra)
set(_terroir_app_modules ${terroir_modules} VTK::CommonCore VTK::CommonDataModel
  VTK::CommonExecutionModel VTK::IOXML VTK::RenderingOpenGL2 VTK::RenderingFreeType
  VTK::InteractionStyle)
target_link_libraries(terroir PRIVATE ${_terroir_app_modules} TerroirTerrainCore
  nlohmann_json::nlohmann_json)
vtk_module_autoinit(TARGETS terroir MODULES ${_terroir_app_modules})
install(TARGETS terroir RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
