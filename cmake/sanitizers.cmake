# Sanitizer and fuzzing instrumentation for every koma target (docs/reliability.md).
#
#   KOMA_SANITIZE=address,undefined  ASan + UBSan, no recovery: the first report aborts the
#                                    process, so a test that trips one fails.
#   KOMA_SANITIZE=thread             TSan.
#   KOMA_BUILD_FUZZERS=ON            libFuzzer's coverage instrumentation on every target
#                                    (fuzzer-no-link), and the fuzz/ targets; needs clang.
#
# Debian's gRPC, protobuf, abseil and gtest are not instrumented: ASan and UBSan still see every
# access koma's own code makes; TSan cannot see gRPC's internal synchronisation, which is why
# the TSan run is limited to tests whose threads koma itself starts (scripts/test-sanitizers.sh).
set(KOMA_SANITIZE "" CACHE STRING "Sanitizers for every target: address,undefined or thread")

if(KOMA_SANITIZE OR KOMA_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "KOMA_SANITIZE / KOMA_BUILD_FUZZERS need clang "
                        "(cmake -DCMAKE_CXX_COMPILER=clang++)")
  endif()
endif()

set(koma_instrument "")
if(KOMA_SANITIZE)
  list(APPEND koma_instrument -fsanitize=${KOMA_SANITIZE} -fno-sanitize-recover=all
       -fno-omit-frame-pointer)
endif()
if(KOMA_BUILD_FUZZERS)
  list(APPEND koma_instrument -fsanitize=fuzzer-no-link)
endif()
if(koma_instrument)
  add_compile_options(${koma_instrument})
  add_link_options(${koma_instrument})
endif()
