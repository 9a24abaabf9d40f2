#include "formats/json_text.h"

#include <cmath>
#include <cstdint>
#include <string>

#include "absl/strings/str_cat.h"

namespace koma::formats {
namespace {

using Json = nlohmann::ordered_json;

// Integers up to this magnitude convert to int64 and back exactly (2^53).
constexpr double kMaxExactInteger = 9007199254740992.0;

// nlohmann's what() without its "[json.exception.parse_error.101] " prefix.
std::string WithoutExceptionId(const char* what) {
  std::string message = what;
  const size_t bracket = message.find("] ");
  if (message.rfind("[json.exception.", 0) == 0 && bracket != std::string::npos) {
    message.erase(0, bracket + 2);
  }
  return message;
}

}  // namespace

absl::Status CheckJsonDepth(std::string_view text, int max_depth) {
  int depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;  // skip the escaped character (it may be a quote)
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) {
        return absl::InvalidArgumentError(
            absl::StrCat("JSON nested deeper than ", max_depth, " levels at byte ", i));
      }
    } else if (c == ']' || c == '}') {
      --depth;  // unbalanced brackets are nlohmann's to report
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<Json> ParseJsonText(std::string_view text) {
  try {
    return Json::parse(text.begin(), text.end());
  } catch (const Json::parse_error& error) {
    // "parse error at line 3, column 5: syntax error while parsing ..."
    return absl::InvalidArgumentError(
        absl::StrCat("invalid JSON at byte ", error.byte, ": ", WithoutExceptionId(error.what())));
  } catch (const Json::exception& error) {
    // out_of_range.406 for numbers such as 1e999, without a position.
    return absl::InvalidArgumentError(
        absl::StrCat("invalid JSON: ", WithoutExceptionId(error.what())));
  }
}

Json JsonNumber(double value) {
  if (value == std::floor(value) && std::fabs(value) <= kMaxExactInteger) {
    return Json(static_cast<int64_t>(value));
  }
  return Json(value);
}

}  // namespace koma::formats
