// What a fuzz target does when a property it checks does not hold: print it and abort, which
// libFuzzer reports as a crash and saves the input that caused it as a reproducer.
#ifndef KOMA_FUZZ_FUZZ_CHECK_H_
#define KOMA_FUZZ_FUZZ_CHECK_H_

#include <cstdio>
#include <cstdlib>

#define KOMA_FUZZ_CHECK(condition, what)                                                          \
  do {                                                                                            \
    if (!(condition)) {                                                                           \
      std::fprintf(stderr, "%s:%d: fuzz check failed: %s (%s)\n", __FILE__, __LINE__, #condition, \
                   what);                                                                         \
      std::abort();                                                                               \
    }                                                                                             \
  } while (0)

#endif  // KOMA_FUZZ_FUZZ_CHECK_H_
