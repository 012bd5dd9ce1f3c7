# Writes mixload_version.hpp with the commit being built (run at every build, so provenance never
# names a stale commit); "-dirty" marks uncommitted changes. configure_file leaves an unchanged
# header untouched, so nothing recompiles when the commit is the same.
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY ${SRC}
  OUTPUT_VARIABLE MIXLOAD_GIT_COMMIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT MIXLOAD_GIT_COMMIT)
  set(MIXLOAD_GIT_COMMIT unknown)
else()
  execute_process(COMMAND git diff --quiet HEAD -- WORKING_DIRECTORY ${SRC} RESULT_VARIABLE dirty)
  if(NOT dirty EQUAL 0)
    set(MIXLOAD_GIT_COMMIT "${MIXLOAD_GIT_COMMIT}-dirty")
  endif()
endif()
set(PROJECT_VERSION ${VERSION})
configure_file(${SRC}/common/version.hpp.in ${OUT} @ONLY)
