# Writes OUTPUT, a header defining KURAGE_COMMIT as `git describe --always --dirty` of SOURCE_DIR
# ("unknown" outside a git checkout), only when it changes, so that a build recompiles the one file
# that includes it only after a commit. Run at every build: cmake -DSOURCE_DIR=... -DOUTPUT=... -P.
set(commit "unknown")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" describe --always --dirty --abbrev=12
                  OUTPUT_VARIABLE described OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE failed)
  if(NOT failed AND described)
    set(commit "${described}")
  endif()
endif()
set(text "#define KURAGE_COMMIT \"${commit}\"\n")
set(old "")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUTPUT}" "${text}")
endif()
