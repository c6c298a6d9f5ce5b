# cmake -DBOLO=<exe> -DARGS=a|b|c -DEXPECT_CODE=N [-DEXPECT_ERR=<regex>] -P expect_exit.cmake
# Runs the executable and checks its exit code and stderr.
string(REPLACE "|" ";" args "${ARGS}")
execute_process(COMMAND "${BOLO}" ${args} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code STREQUAL "${EXPECT_CODE}")
  message(FATAL_ERROR "expected exit code ${EXPECT_CODE}, got ${code}\nstdout: ${out}\nstderr: ${err}")
endif()
if(DEFINED EXPECT_ERR AND NOT err MATCHES "${EXPECT_ERR}")
  message(FATAL_ERROR "stderr does not match '${EXPECT_ERR}':\n${err}")
endif()
