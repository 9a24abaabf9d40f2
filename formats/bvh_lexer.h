// Tokens of a BVH file for the reader (internal to formats/): whitespace-separated words
// with the 1-based line each starts on.
#ifndef KOMA_FORMATS_BVH_LEXER_H_
#define KOMA_FORMATS_BVH_LEXER_H_

#include <cstddef>
#include <string>
#include <string_view>

namespace koma::formats {

struct BvhToken {
  std::string_view text;  // a view into the lexer's input; empty at the end of the input
  int line = 1;           // 1-based
};

// "\"ROOT\"" (quoted as in QuoteForError), or "end of file" for the empty token.
std::string DescribeToken(const BvhToken& token);

// Splits text at spaces, tabs, vertical tabs, form feeds and line ends; LF, CRLF and a lone
// CR each end a line. The text must outlive the lexer and its tokens.
class BvhLexer {
 public:
  explicit BvhLexer(std::string_view text) : text_(text) {}

  // The next token; after the last one, empty tokens on the last line.
  BvhToken Next();

 private:
  void SkipWhitespace();

  std::string_view text_;
  size_t pos_ = 0;
  int line_ = 1;
};

}  // namespace koma::formats

#endif  // KOMA_FORMATS_BVH_LEXER_H_
