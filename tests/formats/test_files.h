// Reads fixture files for the formats tests.
#ifndef KOMA_TESTS_FORMATS_TEST_FILES_H_
#define KOMA_TESTS_FORMATS_TEST_FILES_H_

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace koma::formats {

// The bytes of `path` (binary mode: CRLF stays CRLF); a test failure if it cannot be read.
inline std::string ReadTestFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    ADD_FAILURE() << "cannot open " << path;
    return "";
  }
  std::ostringstream contents;
  contents << in.rdbuf();
  return contents.str();
}

}  // namespace koma::formats

#endif  // KOMA_TESTS_FORMATS_TEST_FILES_H_
