# Sanitizer and fuzzing builds (docs/hardening.md). Applied to every target of the build, so the
# libraries under test are instrumented as well as the tests and fuzz targets that drive them.
#
#   BOLO_SANITIZE  list for -fsanitize=, e.g. "address,undefined" (the `asan` preset); empty: none.
#                  Errors are fatal (-fno-sanitize-recover=all), so ctest sees them as failures.
#   BOLO_FUZZ      the libFuzzer targets in fuzz/ (clang only, the `asan` preset); the fuzz
#                  targets and the libraries they drive get libFuzzer's coverage instrumentation
#                  (-fsanitize=fuzzer-no-link, bolo_fuzz_coverage()), nothing else: the tests,
#                  the CLI and the simulator compile and run without its per-comparison callbacks.
set(BOLO_SANITIZE "" CACHE STRING "Sanitizers for every target (-fsanitize=...), e.g. address,undefined")
option(BOLO_FUZZ "Build the libFuzzer targets in fuzz/ (clang)" OFF)

if(BOLO_SANITIZE)
  add_compile_options(-fsanitize=${BOLO_SANITIZE} -fno-sanitize-recover=all
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${BOLO_SANITIZE})
endif()

# UBSan's vptr check reads the RTTI of polymorphic objects. firmware/ and hal_raw are built with
# -fno-rtti (board code), and host code calls into their LineSink/Stage objects, whose vtables
# carry no type info: the check cannot work across that line, so it is off everywhere, whether
# the sanitizer came through BOLO_SANITIZE or the user's own CMAKE_<LANG>_FLAGS.
string(TOUPPER "${CMAKE_BUILD_TYPE}" _bolo_build_type)
set(_bolo_user_flags "${CMAKE_CXX_FLAGS} ${CMAKE_CXX_FLAGS_${_bolo_build_type}} ${CMAKE_EXE_LINKER_FLAGS}")
if(BOLO_SANITIZE MATCHES "undefined|vptr" OR _bolo_user_flags MATCHES "-fsanitize=[^ ]*(undefined|vptr)")
  add_compile_options(-fno-sanitize=vptr)
  add_link_options(-fno-sanitize=vptr)
endif()

if(BOLO_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "BOLO_FUZZ needs clang (libFuzzer); use the `asan` preset "
                        "(CC=clang CXX=clang++) and Debian's libclang-rt-14-dev")
  endif()
  # Known, reported findings that fuzzing must get past until they are fixed (see the file).
  # Used through a copy named by its hash: neither ninja nor ccache looks into the file, so a
  # changed list must change the command line to rebuild every object with it.
  set(_bolo_ignorelist ${PROJECT_SOURCE_DIR}/fuzz/known-issues.ignorelist)
  file(MD5 ${_bolo_ignorelist} _bolo_ignorelist_md5)
  set(_bolo_ignorelist_copy ${PROJECT_BINARY_DIR}/known-issues-${_bolo_ignorelist_md5}.ignorelist)
  configure_file(${_bolo_ignorelist} ${_bolo_ignorelist_copy} COPYONLY)
  add_compile_options(-fsanitize-ignorelist=${_bolo_ignorelist_copy})
endif()

# Coverage instrumentation for libFuzzer on the given targets (a fuzz target and the libraries it
# drives), where BOLO_FUZZ is on.
function(bolo_fuzz_coverage)
  if(BOLO_FUZZ)
    foreach(target IN LISTS ARGN)
      target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
    endforeach()
  endif()
endfunction()
