#include "formats/json_text.h"

#include <cmath>
#include <cstdint>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "formats/json_fast_read.h"

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

// nlohmann's SAX events built into an ordered_json, the same document nlohmann's own parser
// builds (same values and types; an object's members in file order; a key given twice keeps
// its first position and its last value), without its cost: nlohmann's parser appends each
// member to its object's vector as the key is read, and a vector of pair<const string, json>
// copies (does not move) every member already built each time it grows, so a large object
// was copied whole about twice (profiled: ~10 % of a Spine call). Here an object's members
// are collected first and its vector is made at its final size; the collecting vectors are
// reused per nesting depth.
class OrderedDomBuilder {
 public:
  explicit OrderedDomBuilder(Json& root) : root_(root) {}

  bool null() { return Value(Json(nullptr)); }
  bool boolean(bool value) { return Value(Json(value)); }
  bool number_integer(Json::number_integer_t value) { return Value(Json(value)); }
  bool number_unsigned(Json::number_unsigned_t value) { return Value(Json(value)); }
  bool number_float(Json::number_float_t value, const std::string& /*text*/) {
    return Value(Json(value));
  }
  bool string(std::string& value) { return Value(Json(std::move(value))); }
  bool binary(Json::binary_t& value) { return Value(Json::binary(std::move(value))); }
  bool start_object(std::size_t /*elements*/) { return Open(); }
  bool key(std::string& key) {
    frames_[depth_ - 1].keys.push_back(std::move(key));
    return true;
  }
  bool end_object() {
    Frame& frame = frames_[--depth_];
    Json object(Json::value_t::object);
    // The vector under ordered_map (whose own operator[] looks a key up).
    Json::object_t::Container& members = *object.get_ptr<Json::object_t*>();
    members.reserve(frame.keys.size());
    // A key given twice: nlohmann's parser assigns the later value to the earlier member.
    constexpr size_t kLinearUpTo = 16;
    absl::flat_hash_map<std::string_view, size_t> index;
    for (size_t i = 0; i < frame.keys.size(); ++i) {
      size_t at = members.size();
      if (members.size() <= kLinearUpTo) {
        for (size_t m = 0; m < members.size(); ++m) {
          if (members[m].first == frame.keys[i]) {
            at = m;
            break;
          }
        }
      } else {
        if (index.empty()) {
          for (size_t m = 0; m < members.size(); ++m) index.emplace(members[m].first, m);
        }
        const auto found = index.find(frame.keys[i]);
        if (found != index.end()) at = found->second;
      }
      if (at < members.size()) {
        members[at].second = std::move(frame.values[i]);
        continue;
      }
      members.emplace_back(std::move(frame.keys[i]), std::move(frame.values[i]));
      if (!index.empty()) index.emplace(members.back().first, members.size() - 1);
    }
    frame.keys.clear();
    frame.values.clear();
    return Value(std::move(object));
  }
  bool start_array(std::size_t /*elements*/) { return Open(); }
  bool end_array() {
    Frame& frame = frames_[--depth_];
    Json array(Json::value_t::array);
    array.get_ptr<Json::array_t*>()->assign(std::make_move_iterator(frame.values.begin()),
                                            std::make_move_iterator(frame.values.end()));
    frame.values.clear();
    return Value(std::move(array));
  }
  // As nlohmann's parser with exceptions: the parse_error (or out_of_range for 1e999) itself.
  template <class Exception>
  bool parse_error(std::size_t /*position*/, const std::string& /*last_token*/,
                   const Exception& error) {
    throw error;
  }

 private:
  struct Frame {
    std::vector<std::string> keys;  // an object's keys, in order
    std::vector<Json> values;       // its values, or an array's elements
  };

  bool Open() {
    if (depth_ == frames_.size()) frames_.emplace_back();
    ++depth_;
    return true;
  }
  bool Value(Json&& value) {
    // False stops the parse (the SAX parsers return false): the call was stopped.
    if (stop_.Stop()) return false;
    if (depth_ == 0) {
      root_ = std::move(value);
    } else {
      frames_[depth_ - 1].values.push_back(std::move(value));
    }
    return true;
  }

  Json& root_;
  std::vector<Frame> frames_;  // [0, depth_) open; the rest kept for their capacity
  size_t depth_ = 0;
  StopPoll stop_{/*steps_between_checks=*/1 << 16};  // values: a check every ~2 ms
};

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

namespace {

// Thrown out of a parse the call's stop signal ended (core/stop_check.h).
struct StoppedParse {};

// `parse()`'s document, nlohmann's error as INVALID_ARGUMENT, or why the call stopped.
template <typename Parse>
absl::StatusOr<Json> WithParseStatus(Parse parse) {
  try {
    return parse();
  } catch (const StoppedParse&) {
    return StopReason();
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

// nlohmann's SAX parser into the builder: the document, or its error as INVALID_ARGUMENT.
absl::StatusOr<Json> ParseWithNlohmann(std::string_view text) {
  return WithParseStatus([text] {
    Json document;
    OrderedDomBuilder builder(document);
    if (!Json::sax_parse(text.begin(), text.end(), &builder)) {
      throw StoppedParse();  // the builder said stop (its errors throw nlohmann's exceptions)
    }
    return document;
  });
}

}  // namespace

absl::StatusOr<Json> ParseJsonText(std::string_view text) {
  // Json::parse's document (ParseJsonTextByDom, the tests' reference), built faster: the plain
  // case without nlohmann's lexer; anything else (every error included) is read again by
  // nlohmann, so its errors and edge cases stay its own.
  {
    Json document;
    OrderedDomBuilder builder(document);
    if (json_fast_read::Read(text, builder)) return document;
  }
  KOMA_RETURN_IF_ERROR(StopReason());  // the builder stopped the fast read
  return ParseWithNlohmann(text);
}

absl::StatusOr<Json> ParseJsonTextWithin(std::string_view text, int max_depth) {
  {
    // Deeper than max_depth, or anything else outside the plain case: the two steps below.
    Json document;
    OrderedDomBuilder builder(document);
    if (json_fast_read::Read(text, builder, max_depth)) return document;
  }
  KOMA_RETURN_IF_ERROR(StopReason());  // the builder stopped the fast read
  if (absl::Status depth = CheckJsonDepth(text, max_depth); !depth.ok()) return depth;
  return ParseWithNlohmann(text);
}

absl::StatusOr<Json> ParseJsonTextByDom(std::string_view text) {
  return WithParseStatus([text] { return Json::parse(text.begin(), text.end()); });
}

Json JsonNumber(double value) {
  if (value == std::floor(value) && std::fabs(value) <= kMaxExactInteger) {
    return Json(static_cast<int64_t>(value));
  }
  return Json(value);
}

}  // namespace koma::formats

namespace koma::formats {

void AppendJsonNumber(double value, std::string& out) {
  if (value == std::floor(value) && std::fabs(value) <= kMaxExactInteger) {
    absl::StrAppend(&out, static_cast<int64_t>(value));  // nlohmann's dump_integer: same digits
    return;
  }
  if (!std::isfinite(value)) {
    out += "null";  // nlohmann's dump_float
    return;
  }
  char buffer[64];  // the size of nlohmann's serializer's number buffer
  const char* end = nlohmann::detail::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, static_cast<size_t>(end - buffer));
}

}  // namespace koma::formats
