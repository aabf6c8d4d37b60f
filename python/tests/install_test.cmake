# ctest driver: `cmake --install` of this build into a scratch prefix, then the installed package
# is imported from there by the interpreter it was built for (not from the build tree).
# Arguments: BUILD_DIR, WORK_DIR, PYTHON, PACKAGE_DIR (relative to the prefix).
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${WORK_DIR}"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc}): ${err}")
endif()
set(ENV{PYTHONPATH} "${WORK_DIR}/${PACKAGE_DIR}")
execute_process(
  COMMAND "${PYTHON}" -c
    "import areamatch, sys; p = areamatch.__file__; assert p.startswith(sys.argv[1]), p; import numpy as np; m = areamatch.Map.from_array(np.full((40, 40), 254, np.uint8), 0.05); print('installed areamatch', areamatch.__version__, 'at', p, len(areamatch.segment(m).areas), 'area')"
    "${WORK_DIR}"
  WORKING_DIRECTORY "${WORK_DIR}"  # not the build tree, whose areamatch/ would be found first
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "importing the installed package failed (${rc}): ${out}${err}")
endif()
message("${out}")
