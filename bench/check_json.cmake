# cmake -DBENCH=<path to bolo-bench> -P check_json.cmake
# Runs a quick bench and checks its JSON parses and has the documented shape. Never looks at the
# figures' values: timing goals are reported by bolo-bench, not asserted by tests.
execute_process(COMMAND "${BENCH}" --quick --json --sizes 160x120,32x8
  OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "bolo-bench exited with ${rc}:\n${out}")
endif()
foreach(stage corrector pipeline)
  foreach(size 160x120 32x8)
    foreach(key px_per_s bytes_per_s ratio_to_memcpy)
      string(JSON v ERROR_VARIABLE err GET "${out}" ${stage} ${size} ${key})
      if(err)
        message(FATAL_ERROR "${stage}.${size}.${key}: ${err}\n${out}")
      endif()
    endforeach()
  endforeach()
endforeach()
foreach(size 160x120 32x8)
  string(JSON v ERROR_VARIABLE err GET "${out}" memcpy ${size} bytes_per_s)
  if(err)
    message(FATAL_ERROR "memcpy.${size}.bytes_per_s: ${err}\n${out}")
  endif()
endforeach()
