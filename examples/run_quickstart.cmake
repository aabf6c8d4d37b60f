# Generates a synthetic pair with the CLI and matches it with the quickstart example.
execute_process(COMMAND "${CLI}" generate "${WORK_DIR}" --seed 4 --width 20 --height 14 --rotation 50
                RESULT_VARIABLE generated)
if(NOT generated EQUAL 0)
  message(FATAL_ERROR "areamatch generate failed")
endif()
execute_process(COMMAND "${QUICKSTART}" "${WORK_DIR}/robot.yaml" "${WORK_DIR}/layout.yaml"
                RESULT_VARIABLE matched OUTPUT_VARIABLE out)
message(STATUS "${out}")
if(NOT matched EQUAL 0 OR NOT out MATCHES "area [0-9]+ -> [0-9]+")
  message(FATAL_ERROR "quickstart did not match the generated pair (exit ${matched})")
endif()
execute_process(COMMAND "${QUICKSTART}" "${WORK_DIR}/missing.yaml" "${WORK_DIR}/layout.yaml" RESULT_VARIABLE missing)
if(NOT missing EQUAL 2)
  message(FATAL_ERROR "quickstart on a missing file should exit 2, got ${missing}")
endif()
