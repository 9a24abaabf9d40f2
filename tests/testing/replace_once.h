// The tables of malformed files (tests/formats/*_malformed_test.cc, tests/server/
// file_bad_request_test.cc) break a valid file one way each: this replaces the one place the
// break goes, and fails the test if that place is missing or not unique (a table edit that
// silently changed nothing, or something else, would test the valid file instead).
#ifndef KOMA_TESTS_TESTING_REPLACE_ONCE_H_
#define KOMA_TESTS_TESTING_REPLACE_ONCE_H_

#include <gtest/gtest.h>

#include <string>

namespace koma::testing {

// `text` with the only occurrence of `from` replaced by `to`.
inline std::string ReplaceOnce(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << from << " is not unique";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_TESTING_REPLACE_ONCE_H_
