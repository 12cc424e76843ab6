# SPDX-License-Identifier: MIT
# Warnings and floating-point flags shared by every host target (STYLE.md §6, §9).
# -fno-math-errno changes no value (sqrtf stays the IEEE square root): it only drops the errno
# check around it. Never -ffast-math.
add_library(tumble_flags INTERFACE)
add_library(tumble::flags ALIAS tumble_flags)
target_compile_options(tumble_flags INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -ffp-contract=off -fno-math-errno>
  $<$<AND:$<COMPILE_LANGUAGE:CXX>,$<BOOL:${TUMBLE_WERROR}>>:-Werror>)
# TUMBLE_TEST_NO_LEAK_CHECK: the ENVIRONMENT of the tests whose leaks are not ours under ASan (the
# viewer's, where Mesa's EGL driver keeps 112 bytes to the end of the process; tumble run under
# mpirun, where Open MPI keeps MPI_Init's allocations past MPI_Finalize); empty otherwise.
set(TUMBLE_TEST_NO_LEAK_CHECK "")
# TUMBLE_TEST_SANITIZED: "TUMBLE_TEST_SANITIZED=1" in a sanitizer build (the ENVIRONMENT of the
# end-to-end scripts, whose seed sweeps then run their first seed: examples/tumble/cli_test.sh).
set(TUMBLE_TEST_SANITIZED "")
# TUMBLE_SANITIZE: ON means address,undefined; thread cannot be combined with address.
# (A thread build reports races inside Debian's uninstrumented libtbb: README, "Sanitizers".)
if(TUMBLE_SANITIZE AND NOT TUMBLE_SANITIZE STREQUAL "OFF")
  set(_san "${TUMBLE_SANITIZE}")
  if(_san STREQUAL "ON" OR _san STREQUAL "TRUE" OR _san STREQUAL "1")
    set(_san "address,undefined")
  endif()
  string(REPLACE "," ";" _san_list "${_san}")
  foreach(_s IN LISTS _san_list)
    if(NOT _s MATCHES "^(address|undefined|thread)$")
      message(FATAL_ERROR "TUMBLE_SANITIZE: unknown sanitizer '${_s}' (expected address, undefined or thread)")
    endif()
  endforeach()
  if("address" IN_LIST _san_list AND "thread" IN_LIST _san_list)
    message(FATAL_ERROR "TUMBLE_SANITIZE: address and thread cannot be combined")
  endif()
  target_compile_options(tumble_flags INTERFACE -fsanitize=${_san} -fno-omit-frame-pointer)
  if("undefined" IN_LIST _san_list)  # a report fails the test instead of scrolling past
    target_compile_options(tumble_flags INTERFACE -fno-sanitize-recover=undefined)
  endif()
  target_link_options(tumble_flags INTERFACE -fsanitize=${_san})
  if("address" IN_LIST _san_list)
    set(TUMBLE_TEST_NO_LEAK_CHECK "ASAN_OPTIONS=detect_leaks=0")
  endif()
  set(TUMBLE_TEST_SANITIZED "TUMBLE_TEST_SANITIZED=1")
  set(TUMBLE_SANITIZE_LINK -fsanitize=${_san})  # what a consumer of the installed library links too
  message(STATUS "tumble: sanitizers ${_san}")
endif()
# TUMBLE_FUZZ: every host target gets libFuzzer's coverage instrumentation (the fuzz targets
# themselves link -fsanitize=fuzzer: validation/fuzz).
if(TUMBLE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "TUMBLE_FUZZ needs Clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++-14")
  endif()
  target_compile_options(tumble_flags INTERFACE -fsanitize=fuzzer-no-link)
  message(STATUS "tumble: libFuzzer instrumentation")
endif()
