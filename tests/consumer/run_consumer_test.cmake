# ctest driver: builds tests/consumer against areamatch (installed, or via add_subdirectory) and runs it.
# Arguments: SOURCE_DIR (areamatch), WORK_DIR (scratch), MODE (find_package | add_subdirectory), GENERATOR,
# BUILD_TYPE (the consumer's CMAKE_BUILD_TYPE; empty: none, CMake's default for a user who sets none).
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY "${WORK_DIR}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message("${out}")
endfunction()

set(consumer_args -DAREAMATCH_CONSUMER_MODE=${MODE})
if(MODE STREQUAL "find_package")
  run(${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${WORK_DIR}/areamatch-build" -G "${GENERATOR}"
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=${WORK_DIR}/prefix
      -DAREAMATCH_BUILD_TESTS=OFF -DAREAMATCH_BUILD_EXAMPLES=OFF
      -DAREAMATCH_BUILD_BENCHMARKS=OFF -DAREAMATCH_BUILD_TOOLS=OFF -DAREAMATCH_BUILD_PYTHON=OFF)
  run(${CMAKE_COMMAND} --install "${WORK_DIR}/areamatch-build")
  list(APPEND consumer_args -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
else()
  list(APPEND consumer_args -DAREAMATCH_SOURCE_DIR=${SOURCE_DIR})
endif()
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/consumer" -B "${WORK_DIR}/consumer-build" -G "${GENERATOR}"
    "-DCMAKE_BUILD_TYPE=${BUILD_TYPE}" ${consumer_args})
run(${CMAKE_COMMAND} --build "${WORK_DIR}/consumer-build")
run("${WORK_DIR}/consumer-build/consumer" "${WORK_DIR}")
