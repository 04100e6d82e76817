# Helpers shared by the Terroir modules.

# terroir_add_core_library(<name> SOURCES ...)
# A plain C++ static library (PIC) that must not see VTK or GL: it gets no VTK include
# directories, so a stray VTK include fails to compile.
function(terroir_add_core_library name)
  cmake_parse_arguments(arg "" "" "SOURCES;LIBRARIES" ${ARGN})
  add_library(${name} STATIC ${arg_SOURCES})
  target_include_directories(${name} PUBLIC
    "$<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}>"
    "$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/terroir>")
  target_compile_features(${name} PUBLIC cxx_std_17)
  target_compile_options(${name} PRIVATE -Wall -Wextra)
  set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  if(arg_LIBRARIES)
    target_link_libraries(${name} PUBLIC ${arg_LIBRARIES})
  endif()
  install(TARGETS ${name} EXPORT Terroir ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}")
endfunction()

# terroir_embed_shaders(<export-macro-prefix> <library-name> <sources-var> <headers-var> stem...)
# Embeds Shaders/<stem>.comp as `extern const char* vtkTerroir<stem>CS;` (header
# vtkTerroir<stem>CS.h in the current binary dir), as VTK's Rendering/OpenGL2 does.
function(terroir_embed_shaders export_prefix library sources_var headers_var)
  include("${VTK_DIR}/vtkEncodeString.cmake")
  set(_srcs)
  set(_hdrs)
  foreach(stem IN LISTS ARGN)
    vtk_encode_string(
      INPUT "${PROJECT_SOURCE_DIR}/Shaders/${stem}.comp"
      NAME "vtkTerroir${stem}CS"
      EXPORT_SYMBOL "${export_prefix}_NO_EXPORT"
      EXPORT_HEADER "${library}Module.h"
      HEADER_OUTPUT _hdr
      SOURCE_OUTPUT _src)
    list(APPEND _srcs "${_src}")
    list(APPEND _hdrs "${_hdr}")
  endforeach()
  set(${sources_var} ${_srcs} PARENT_SCOPE)
  set(${headers_var} ${_hdrs} PARENT_SCOPE)
endfunction()
