# Run at every build (not only at configure time), so a report's
# provenance names the revision the binaries were built from.
#   cmake -DSOURCE_DIR=... -DGIT=... -DVERSION=... -DIN=build_info.cpp.in -DOUT=build_info.cpp -P git_revision.cmake
# configure_file rewrites OUT only when its text changes: no rebuild when
# the revision is the same.
set(LISTA_GIT_REVISION "unknown")
if(GIT)
  execute_process(COMMAND ${GIT} describe --always --dirty
                  WORKING_DIRECTORY ${SOURCE_DIR}
                  OUTPUT_VARIABLE rev OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE rev_rc ERROR_QUIET)
  if(rev_rc EQUAL 0 AND rev)
    set(LISTA_GIT_REVISION "${rev}")
  endif()
endif()
set(PROJECT_VERSION "${VERSION}")
configure_file(${IN} ${OUT} @ONLY)
