// Shared by motion3_reader.cc and motion3_writer.cc: typed access to nlohmann::ordered_json
// values with errors that name the JSON path, and the Curves/Segments walk that both parsing
// and counting use. Not part of the public formats API.
#ifndef KOMA_FORMATS_MOTION3_INTERNAL_H_
#define KOMA_FORMATS_MOTION3_INTERNAL_H_

#include <nlohmann/json.hpp>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/curves.h"

namespace koma::formats::motion3_internal {

using Json = nlohmann::ordered_json;

// `value` for an error message: a string quoted (QuoteForError), a number as FormatDouble
// writes it, true/false/null as such, "an array" or "an object".
std::string DescribeJson(const Json& value);

// INVALID_ARGUMENT "<path>: <message>".
absl::Status PathError(const std::string& path, const std::string& message);

// "Meta" + "Fps" -> "Meta.Fps"; "" + "Meta" -> "Meta".
std::string MemberPath(const std::string& object_path, const char* key);

// The member `key` of the object `object` (at `object_path`); nullptr when absent.
const Json* FindMember(const Json& object, const char* key);
// Like FindMember, but INVALID_ARGUMENT "<path>.<key>: missing" when absent.
absl::StatusOr<const Json*> RequireMember(const Json& object, const std::string& object_path,
                                          const char* key);

// `value` as a finite double, or INVALID_ARGUMENT "<path>: expected a (finite) number, got
// ...".
absl::StatusOr<double> NumberAt(const Json& value, const std::string& path);
// `value` as a string, or INVALID_ARGUMENT "<path>: expected a string, got ...".
absl::StatusOr<std::string> StringAt(const Json& value, const std::string& path);
// OK when `value` is an object, else INVALID_ARGUMENT "<path>: expected an object, got ...".
absl::Status RequireObject(const Json& value, const std::string& path);
// OK when `value` is an array, else INVALID_ARGUMENT "<path>: expected an array, got ...".
absl::Status RequireArray(const Json& value, const std::string& path);

// One entry of Curves, checked: Target one of "Model", "Parameter", "PartOpacity"; Id a
// string; FadeInTime/FadeOutTime numbers when present; Segments as in ReadSegments.
struct CurveEntry {
  std::string target;
  Curve curve;  // id set; times still in seconds
};
absl::StatusOr<CurveEntry> ReadCurveEntry(const Json& entry, int index);

// A Segments array (at `path`) as a keyframe curve with times in seconds (CurvePoint::frame
// holds seconds here). Requires finite numbers, the first point and at least one segment,
// known identifiers written as integers (0 to 3), and complete segments.
absl::StatusOr<Curve> ReadSegments(const Json& segments, const std::string& path);

}  // namespace koma::formats::motion3_internal

#endif  // KOMA_FORMATS_MOTION3_INTERNAL_H_
