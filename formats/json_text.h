// JSON text in and out for the JSON-based formats (motion3.json, Spine JSON): a depth check
// before parsing, nlohmann's parse errors as INVALID_ARGUMENT with the byte offset, and numbers
// written as integers when they are whole.
#ifndef KOMA_FORMATS_JSON_TEXT_H_
#define KOMA_FORMATS_JSON_TEXT_H_

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace koma::formats {

// OK when no bracket nests deeper than `max_depth` (one pass over the bytes; brackets inside
// strings do not count), so a hostile file cannot exhaust the stack in nlohmann's recursive
// parser or dump. Else INVALID_ARGUMENT "JSON nested deeper than N levels at byte B".
absl::Status CheckJsonDepth(std::string_view text, int max_depth);

// The whole text as an ordered_json (object keys in file order). INVALID_ARGUMENT "invalid JSON
// at byte B: parse error at line L, column C: ..." for malformed text.
absl::StatusOr<nlohmann::ordered_json> ParseJsonText(std::string_view text);

// CheckJsonDepth(text, max_depth), then ParseJsonText(text): the same status and document, in
// one pass over the text when it is plain JSON no deeper than max_depth (the depth check then
// needs no pass of its own).
absl::StatusOr<nlohmann::ordered_json> ParseJsonTextWithin(std::string_view text, int max_depth);

// The same with nlohmann's own parser (Json::parse): the reference ParseJsonText is tested
// against (it builds the same document at about half the cost).
absl::StatusOr<nlohmann::ordered_json> ParseJsonTextByDom(std::string_view text);

// 2.0 -> JSON 2, -0.0 -> 0, 0.5 -> 0.5 (nlohmann dumps doubles with the shortest round-trip
// text, so 10.0 / 30.0 -> 0.3333333333333333).
nlohmann::ordered_json JsonNumber(double value);

// Appends to `out` the text nlohmann's dump writes for JsonNumber(value), byte for byte (its
// integer printing, or its own shortest-double routine, nlohmann::detail::to_chars; "null" for
// NaN and infinities), without making the JSON value or going through a serializer.
void AppendJsonNumber(double value, std::string& out);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_JSON_TEXT_H_
