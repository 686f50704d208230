# svr_embedded_files(LIBRARY DIR dir FILES a b … HEADER h TYPE T FUNCTION f COMMENT text)
# A static library holding the files of `dir` as byte arrays, made at build time by
# EmbedFiles.cmake: HEADER declares T {path, content_type, bytes} and `const T* svr::f(path)`,
# which the library defines. The viewer's page (harness/view/) and the gl backend's shaders
# (renderers/gl/) are embedded so; editing a file rebuilds the library.
function(svr_embedded_files library)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "DIR;HEADER;TYPE;FUNCTION;COMMENT" "FILES")
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${library}.cpp)
  set(paths "")
  foreach(f IN LISTS ARG_FILES)
    list(APPEND paths ${ARG_DIR}/${f})
  endforeach()
  string(REPLACE ";" "," names "${ARG_FILES}")
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DDIR=${ARG_DIR} -DFILES=${names}
            -DHEADER=${ARG_HEADER} -DTYPE=${ARG_TYPE} -DFUNCTION=${ARG_FUNCTION}
            -P ${PROJECT_SOURCE_DIR}/cmake/EmbedFiles.cmake
    DEPENDS ${paths} ${PROJECT_SOURCE_DIR}/cmake/EmbedFiles.cmake
    COMMENT "${ARG_COMMENT}"
    VERBATIM)
  add_library(${library} STATIC ${out})
  target_include_directories(${library} PUBLIC ${PROJECT_SOURCE_DIR})
endfunction()
