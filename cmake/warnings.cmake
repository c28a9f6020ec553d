# One INTERFACE target carries reel's warnings and determinism flags; every reel target links it.
add_library(reel_options INTERFACE)
target_compile_options(reel_options INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Wnon-virtual-dtor
  # Determinism (DESIGN 6): no fused multiply-add contraction, no fast-math.
  -ffp-contract=off -fno-fast-math
  # Square roots need not set errno, so they vectorize; no value changes.
  -fno-math-errno)
if(NOT REEL_TARGET_CLONES)
  target_compile_definitions(reel_options INTERFACE REEL_NO_CLONES)
endif()
if(REEL_SANITIZE)
  target_compile_options(reel_options INTERFACE -fsanitize=${REEL_SANITIZE} -fno-omit-frame-pointer)
  target_link_options(reel_options INTERFACE -fsanitize=${REEL_SANITIZE})
endif()
if(REEL_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "REEL_FUZZ needs clang (libFuzzer): use the fuzz preset")
  endif()
  # Coverage instrumentation for libFuzzer in every reel library; the targets link the driver.
  target_compile_options(reel_options INTERFACE -fsanitize=fuzzer-no-link)
endif()
target_compile_definitions(reel_options INTERFACE
  REEL_VERSION="${PROJECT_VERSION}" REEL_BUILD_TYPE="${CMAKE_BUILD_TYPE}")
