# SPDX-License-Identifier: MIT
# Warnings and floating-point flags shared by every host target (STYLE.md §6, §9).
# -fno-math-errno changes no value (sqrtf stays the IEEE square root): it only drops the errno
# check around it. Never -ffast-math.
add_library(tumble_flags INTERFACE)
add_library(tumble::flags ALIAS tumble_flags)
target_compile_options(tumble_flags INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -ffp-contract=off -fno-math-errno>
  $<$<AND:$<COMPILE_LANGUAGE:CXX>,$<BOOL:${TUMBLE_WERROR}>>:-Werror>)
if(TUMBLE_SANITIZE)
  target_compile_options(tumble_flags INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer)
  target_link_options(tumble_flags INTERFACE -fsanitize=address,undefined)
endif()
