# Flags for code that runs on the camera board: no exceptions, no RTTI, strict warnings.
# Applied per target so host code (sim/, apps/) keeps exceptions.
function(bolo_firmware_target target)
  get_target_property(kind ${target} TYPE)
  if(kind STREQUAL "INTERFACE_LIBRARY")
    return()
  endif()
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti>
    -Wall -Wextra -Wconversion -Wsign-conversion -Wshadow
    $<$<BOOL:${BOLO_WERROR}>:-Werror>)
endfunction()
