// FNV-1a, 64 bits: a fixed, portable fingerprint of bytes, for tests that pin an answer's
// exact bytes without storing them.
#ifndef KOMA_TESTS_TESTING_FNV1A_H_
#define KOMA_TESTS_TESTING_FNV1A_H_

#include <cstdint>
#include <string>

namespace koma::testing {

inline uint64_t Fnv1a64(const std::string& bytes) {
  uint64_t hash = 0xcbf29ce484222325ULL;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_TESTING_FNV1A_H_
