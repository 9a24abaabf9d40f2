// A JSON reader for the common case, feeding nlohmann's SAX events (formats/json_text.cc's
// document builder) faster than nlohmann's own lexer: it reads from a contiguous buffer rather
// than through an iterator adapter a character at a time, and reads numbers with
// std::from_chars (correctly rounded, as glibc's strtod that nlohmann calls, but without the
// locale and the token copy). Profiled on a 50-bone Spine skeleton: nlohmann's lexer and strtod
// were ~25 % of a RetimeCurves call.
//
// It gives up (returns false) on anything outside the plain case, and the caller then parses
// the text again with nlohmann: invalid JSON of any kind (so every error message stays
// nlohmann's), a byte-order mark, \u escapes, a number from_chars reports out of range (1e999,
// 1e-400), and nesting deeper than kMaxFastJsonDepth (this reader recurses; nlohmann does not).
// When it returns true the events are those nlohmann's parser sends for the same text: the
// same values and types (unsigned for a non-negative integer, integer for a negative one, float
// with a '.' or an exponent or for an integer that overflows 64 bits), keys in order.
#ifndef KOMA_FORMATS_JSON_FAST_READ_H_
#define KOMA_FORMATS_JSON_FAST_READ_H_

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>

namespace koma::formats::json_fast_read {

// Deeper nesting is left to nlohmann (which keeps its own stack rather than recursing).
inline constexpr int kMaxFastJsonDepth = 256;

template <class Sax>
class Reader {
 public:
  Reader(std::string_view text, Sax& sax, int max_depth)
      : p_(text.data()), end_(text.data() + text.size()), sax_(sax), max_depth_(max_depth) {}

  // True when the whole text was one JSON value (whitespace around it) read in the plain case.
  bool ReadDocument() {
    if (p_ != end_ && static_cast<unsigned char>(*p_) == 0xEF) return false;  // a BOM
    SkipWhitespace();
    if (!Value(0)) return false;
    SkipWhitespace();
    return p_ == end_;
  }

 private:
  void SkipWhitespace() {
    while (p_ != end_ && (*p_ == ' ' || *p_ == '\n' || *p_ == '\r' || *p_ == '\t')) ++p_;
  }

  bool Value(int depth) {
    if (p_ == end_) return false;
    switch (*p_) {
      case '{':
        return Object(depth + 1);
      case '[':
        return Array(depth + 1);
      case '"': {
        std::string value;
        if (!String(value)) return false;
        return sax_.string(value);
      }
      case 't':
        return Literal("true") && sax_.boolean(true);
      case 'f':
        return Literal("false") && sax_.boolean(false);
      case 'n':
        return Literal("null") && sax_.null();
      default:
        return Number();
    }
  }

  bool Object(int depth) {
    if (depth > max_depth_) return false;
    ++p_;  // '{'
    sax_.start_object(static_cast<std::size_t>(-1));
    SkipWhitespace();
    if (p_ != end_ && *p_ == '}') {
      ++p_;
      return sax_.end_object();
    }
    std::string key;
    while (true) {
      if (p_ == end_ || *p_ != '"') return false;
      key.clear();
      if (!String(key)) return false;
      sax_.key(key);
      SkipWhitespace();
      if (p_ == end_ || *p_ != ':') return false;
      ++p_;
      SkipWhitespace();
      if (!Value(depth)) return false;
      SkipWhitespace();
      if (p_ == end_) return false;
      if (*p_ == '}') {
        ++p_;
        return sax_.end_object();
      }
      if (*p_ != ',') return false;
      ++p_;
      SkipWhitespace();
    }
  }

  bool Array(int depth) {
    if (depth > max_depth_) return false;
    ++p_;  // '['
    sax_.start_array(static_cast<std::size_t>(-1));
    SkipWhitespace();
    if (p_ != end_ && *p_ == ']') {
      ++p_;
      return sax_.end_array();
    }
    while (true) {
      if (!Value(depth)) return false;
      SkipWhitespace();
      if (p_ == end_) return false;
      if (*p_ == ']') {
        ++p_;
        return sax_.end_array();
      }
      if (*p_ != ',') return false;
      ++p_;
      SkipWhitespace();
    }
  }

  bool Literal(std::string_view word) {
    if (static_cast<size_t>(end_ - p_) < word.size() || std::string_view(p_, word.size()) != word) {
      return false;
    }
    p_ += word.size();
    return true;
  }

  // The string starting at the quote under p_, unescaped into `out`. Bytes below 0x20 are
  // refused (as nlohmann does); bytes from 0x80 must be well-formed UTF-8 (RFC 3629, the check
  // nlohmann makes).
  bool String(std::string& out) {
    ++p_;  // '"'
    while (true) {
      const char* run = p_;
      while (p_ != end_) {
        const auto c = static_cast<unsigned char>(*p_);
        if (c == '"' || c == '\\' || c < 0x20 || c >= 0x80) break;
        ++p_;
      }
      out.append(run, p_);
      if (p_ == end_) return false;
      const auto c = static_cast<unsigned char>(*p_);
      if (c == '"') {
        ++p_;
        return true;
      }
      if (c < 0x20) return false;
      if (c >= 0x80) {
        const int length = Utf8Length();
        if (length == 0) return false;
        out.append(p_, p_ + length);
        p_ += length;
        continue;
      }
      // A backslash: the escapes but \u (left to nlohmann: surrogate pairs and their errors).
      if (++p_ == end_) return false;
      switch (*p_) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        default: return false;
      }
      ++p_;
    }
  }

  // The length of the well-formed UTF-8 sequence at p_ (Unicode Table 3-7), or 0.
  int Utf8Length() const {
    const auto at = [this](std::ptrdiff_t i) -> int {
      return p_ + i < end_ ? static_cast<unsigned char>(p_[i]) : -1;
    };
    const auto in = [](int c, int lo, int hi) { return c >= lo && c <= hi; };
    const int b0 = at(0);
    if (in(b0, 0xC2, 0xDF)) return in(at(1), 0x80, 0xBF) ? 2 : 0;
    if (b0 == 0xE0) return in(at(1), 0xA0, 0xBF) && in(at(2), 0x80, 0xBF) ? 3 : 0;
    if (in(b0, 0xE1, 0xEC) || b0 == 0xEE || b0 == 0xEF) {
      return in(at(1), 0x80, 0xBF) && in(at(2), 0x80, 0xBF) ? 3 : 0;
    }
    if (b0 == 0xED) return in(at(1), 0x80, 0x9F) && in(at(2), 0x80, 0xBF) ? 3 : 0;
    if (b0 == 0xF0) {
      return in(at(1), 0x90, 0xBF) && in(at(2), 0x80, 0xBF) && in(at(3), 0x80, 0xBF) ? 4 : 0;
    }
    if (in(b0, 0xF1, 0xF3)) {
      return in(at(1), 0x80, 0xBF) && in(at(2), 0x80, 0xBF) && in(at(3), 0x80, 0xBF) ? 4 : 0;
    }
    if (b0 == 0xF4) {
      return in(at(1), 0x80, 0x8F) && in(at(2), 0x80, 0xBF) && in(at(3), 0x80, 0xBF) ? 4 : 0;
    }
    return 0;
  }

  static bool Digit(char c) { return c >= '0' && c <= '9'; }

  // JSON's number grammar, then its value as nlohmann types it.
  bool Number() {
    const char* start = p_;
    const bool negative = *p_ == '-';
    if (negative) ++p_;
    if (p_ == end_) return false;
    if (*p_ == '0') {
      ++p_;
    } else if (Digit(*p_)) {
      while (p_ != end_ && Digit(*p_)) ++p_;
    } else {
      return false;
    }
    bool is_float = false;
    if (p_ != end_ && *p_ == '.') {
      is_float = true;
      ++p_;
      if (p_ == end_ || !Digit(*p_)) return false;
      while (p_ != end_ && Digit(*p_)) ++p_;
    }
    if (p_ != end_ && (*p_ == 'e' || *p_ == 'E')) {
      is_float = true;
      ++p_;
      if (p_ != end_ && (*p_ == '+' || *p_ == '-')) ++p_;
      if (p_ == end_ || !Digit(*p_)) return false;
      while (p_ != end_ && Digit(*p_)) ++p_;
    }
    if (!is_float) {
      // nlohmann: strtoull / strtoll, and a float when they overflow.
      if (negative) {
        int64_t value = 0;
        const auto [ptr, ec] = std::from_chars(start, p_, value);
        if (ec == std::errc() && ptr == p_) return sax_.number_integer(value);
      } else {
        uint64_t value = 0;
        const auto [ptr, ec] = std::from_chars(start, p_, value);
        if (ec == std::errc() && ptr == p_) return sax_.number_unsigned(value);
      }
    }
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(start, p_, value);
    if (ec != std::errc() || ptr != p_ || !std::isfinite(value)) return false;
    static const std::string kNoText;  // the builder does not read the number's text
    return sax_.number_float(value, kNoText);
  }

  const char* p_;
  const char* const end_;
  Sax& sax_;
  const int max_depth_;  // brackets nested deeper: not the plain case
};

// Reads `text` into `sax`; false when the text is outside the plain case (the caller then
// starts again with a fresh Sax and nlohmann's parser), including brackets nested deeper than
// max_depth (at most kMaxFastJsonDepth; the outermost bracket is depth 1, as CheckJsonDepth
// counts).
template <class Sax>
bool Read(std::string_view text, Sax& sax, int max_depth = kMaxFastJsonDepth) {
  return Reader<Sax>(text, sax, std::min(max_depth, kMaxFastJsonDepth)).ReadDocument();
}

}  // namespace koma::formats::json_fast_read

#endif  // KOMA_FORMATS_JSON_FAST_READ_H_
