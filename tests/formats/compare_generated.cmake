# cmake -DPYTHON=... -DSCRIPT=... -DEXPECTED=... -DOUTPUT=... -P compare_generated.cmake
# Runs the generator SCRIPT into OUTPUT and fails unless OUTPUT equals EXPECTED byte for byte.
execute_process(COMMAND ${PYTHON} ${SCRIPT} ${OUTPUT} RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${SCRIPT} failed: ${result}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${EXPECTED} ${OUTPUT}
  RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${OUTPUT} differs from ${EXPECTED}: rerun ${SCRIPT} and commit")
endif()
