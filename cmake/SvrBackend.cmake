# Backends (renderers/NAME/, one line in renderers/registry.cpp's list). A backend folder's
# CMakeLists.txt calls one of:
#   svr_backend(NAME SOURCES a.cpp … [LIBRARIES lib …])
#       builds the backend into svr_renderers; its sources define svr::backends::NAME().
#   svr_backend_unavailable(NAME "why, and what to install")
#       the backend cannot be built here: the registry lists it as not built, with that reason,
#       and its tests (tests/renderers/NAME/) are replaced by one that skips saying so.
# The global property SVR_BACKENDS_BUILT lists the backends built.

function(svr_backend name)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "" "SOURCES;LIBRARIES")
  target_sources(svr_renderers PRIVATE ${ARG_SOURCES})
  if(ARG_LIBRARIES)
    target_link_libraries(svr_renderers PRIVATE ${ARG_LIBRARIES})
  endif()
  set_property(GLOBAL APPEND PROPERTY SVR_BACKENDS_BUILT ${name})
endfunction()

function(svr_backend_unavailable name why)
  message(STATUS "svr: backend '${name}' is not built: ${why}")
  set(SVR_BACKEND_NAME ${name})
  set(SVR_BACKEND_WHY ${why})
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${name}_unavailable.cpp)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/backend_unavailable.cpp.in ${out} @ONLY)
  target_sources(svr_renderers PRIVATE ${out})
  set_property(GLOBAL PROPERTY SVR_BACKEND_WHY_${name} "${why}")
endfunction()
