# Memory-error and fuzzing builds (docs/robustness.md). Both are separate build trees, never the
# Release build: scripts/test-sanitizers.sh configures NAVAID_SANITIZE, scripts/fuzz.sh adds
# NAVAID_BUILD_FUZZERS on the same tree.
option(NAVAID_SANITIZE "Build everything with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(NAVAID_BUILD_FUZZERS "Build the libFuzzer harnesses in tests/fuzz (clang only)" OFF)

if(NAVAID_SANITIZE)
  # Every finding stops the program (no recovery), so a test cannot pass over one.
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()

if(NAVAID_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang" OR NOT CMAKE_C_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "NAVAID_BUILD_FUZZERS needs clang for C and C++ (libFuzzer): "
      "configure with -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++")
  endif()
  if(NOT NAVAID_SANITIZE)
    message(FATAL_ERROR "NAVAID_BUILD_FUZZERS needs NAVAID_SANITIZE=ON: a fuzzer without "
      "AddressSanitizer misses the memory errors it is for")
  endif()
endif()

# Rooms whose code parses outside input get libFuzzer's coverage instrumentation; the rest stays
# uninstrumented so the sanitized test suite is not slowed by it.
set(NAVAID_FUZZED_ROOMS core io planning interaction)
function(navaid_fuzz_instrument target)
  if(NAVAID_BUILD_FUZZERS)
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()
