#include "formats/bvh_lexer.h"

#include "formats/error_text.h"

namespace koma::formats {
namespace {

bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

}  // namespace

std::string DescribeToken(const BvhToken& token) {
  if (token.text.empty()) return "end of file";
  return QuoteForError(token.text);
}

BvhToken BvhLexer::Next() {
  SkipWhitespace();
  const size_t start = pos_;
  while (pos_ < text_.size() && !IsSpace(text_[pos_])) ++pos_;
  return BvhToken{text_.substr(start, pos_ - start), line_};
}

void BvhLexer::SkipWhitespace() {
  for (; pos_ < text_.size() && IsSpace(text_[pos_]); ++pos_) {
    const char c = text_[pos_];
    const bool cr_of_crlf = c == '\r' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '\n';
    if ((c == '\n' || c == '\r') && !cr_of_crlf) ++line_;
  }
}

}  // namespace koma::formats
