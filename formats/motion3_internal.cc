#include "formats/motion3_internal.h"

#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <utility>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "formats/error_text.h"
#include "formats/number_format.h"

namespace koma::formats::motion3_internal {
namespace {

constexpr const char* kTargets[] = {"Model", "Parameter", "PartOpacity"};

std::string IndexPath(const std::string& array_path, size_t index) {
  return absl::StrCat(array_path, "[", index, "]");
}

// Reads the point at segments[at], segments[at + 1] (time in seconds, value).
absl::StatusOr<CurvePoint> ReadPoint(const Json& segments, size_t at, const std::string& path) {
  CurvePoint point;
  KOMA_ASSIGN_OR_RETURN(point.frame, NumberAt(segments[at], IndexPath(path, at)));
  KOMA_ASSIGN_OR_RETURN(point.value, NumberAt(segments[at + 1], IndexPath(path, at + 1)));
  return point;
}

// The identifier at segments[at]: exactly 0, 1, 2 or 3 (the SDK would truncate 1.5 to 1;
// such a file is broken, so it is refused).
absl::StatusOr<SegmentType> ReadSegmentType(const Json& segments, size_t at,
                                            const std::string& path) {
  const std::string here = IndexPath(path, at);
  KOMA_ASSIGN_OR_RETURN(const double id, NumberAt(segments[at], here));
  if (id == 0.0) return SegmentType::kLinear;
  if (id == 1.0) return SegmentType::kBezier;
  if (id == 2.0) return SegmentType::kStepped;
  if (id == 3.0) return SegmentType::kInverseStepped;
  return PathError(here, absl::StrCat("unknown segment identifier ", FormatDouble(id),
                                      " (expected 0 linear, 1 bezier, 2 stepped or 3 "
                                      "inverse stepped)"));
}

const char* SegmentTypeName(SegmentType type) {
  switch (type) {
    case SegmentType::kLinear:
      return "linear";
    case SegmentType::kBezier:
      return "bezier";
    case SegmentType::kStepped:
      return "stepped";
    case SegmentType::kInverseStepped:
      return "inverse stepped";
  }
  return "unknown";  // not reached for a valid enum value
}

absl::Status CheckTarget(const std::string& target, const std::string& path) {
  for (const char* known : kTargets) {
    if (target == known) return absl::OkStatus();
  }
  return PathError(path, absl::StrCat("expected \"Model\", \"Parameter\" or \"PartOpacity\", got ",
                                      QuoteForError(target)));
}

}  // namespace

std::string DescribeJson(const Json& value) {
  switch (value.type()) {
    case Json::value_t::string:
      return QuoteForError(value.get_ref<const std::string&>());
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float:
      return FormatDouble(value.get<double>());
    case Json::value_t::boolean:
      return value.get<bool>() ? "true" : "false";
    case Json::value_t::array:
      return "an array";
    case Json::value_t::object:
      return "an object";
    default:
      return "null";  // null, and the binary/discarded kinds a parsed document never holds
  }
}

absl::Status PathError(const std::string& path, const std::string& message) {
  return absl::InvalidArgumentError(absl::StrCat(path, ": ", message));
}

std::string MemberPath(const std::string& object_path, const char* key) {
  return object_path.empty() ? std::string(key) : absl::StrCat(object_path, ".", key);
}

const Json* FindMember(const Json& object, const char* key) {
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

absl::StatusOr<const Json*> RequireMember(const Json& object, const std::string& object_path,
                                          const char* key) {
  const Json* member = FindMember(object, key);
  if (member == nullptr) return PathError(MemberPath(object_path, key), "missing");
  return member;
}

absl::StatusOr<double> NumberAt(const Json& value, const std::string& path) {
  if (!value.is_number()) {
    return PathError(path, absl::StrCat("expected a number, got ", DescribeJson(value)));
  }
  const double number = value.get<double>();
  // nlohmann reads 1e999 as infinity.
  if (!std::isfinite(number)) {
    return PathError(path, absl::StrCat("expected a finite number, got ", FormatDouble(number)));
  }
  return number;
}

absl::StatusOr<std::string> StringAt(const Json& value, const std::string& path) {
  if (!value.is_string()) {
    return PathError(path, absl::StrCat("expected a string, got ", DescribeJson(value)));
  }
  return value.get<std::string>();
}

absl::Status RequireObject(const Json& value, const std::string& path) {
  if (value.is_object()) return absl::OkStatus();
  return PathError(path, absl::StrCat("expected an object, got ", DescribeJson(value)));
}

absl::Status RequireArray(const Json& value, const std::string& path) {
  if (value.is_array()) return absl::OkStatus();
  return PathError(path, absl::StrCat("expected an array, got ", DescribeJson(value)));
}

absl::StatusOr<CurveEntry> ReadCurveEntry(const Json& entry, int index) {
  const std::string path = IndexPath("Curves", static_cast<size_t>(index));
  KOMA_RETURN_IF_ERROR(RequireObject(entry, path));
  CurveEntry result;
  KOMA_ASSIGN_OR_RETURN(const Json* target, RequireMember(entry, path, "Target"));
  KOMA_ASSIGN_OR_RETURN(result.target, StringAt(*target, MemberPath(path, "Target")));
  KOMA_RETURN_IF_ERROR(CheckTarget(result.target, MemberPath(path, "Target")));
  KOMA_ASSIGN_OR_RETURN(const Json* id, RequireMember(entry, path, "Id"));
  KOMA_ASSIGN_OR_RETURN(std::string id_text, StringAt(*id, MemberPath(path, "Id")));
  for (const char* fade : {"FadeInTime", "FadeOutTime"}) {
    const Json* time = FindMember(entry, fade);
    if (time != nullptr) KOMA_RETURN_IF_ERROR(NumberAt(*time, MemberPath(path, fade)).status());
  }
  KOMA_ASSIGN_OR_RETURN(const Json* segments, RequireMember(entry, path, "Segments"));
  KOMA_ASSIGN_OR_RETURN(result.curve, ReadSegments(*segments, MemberPath(path, "Segments")));
  result.curve.id = std::move(id_text);
  return result;
}

absl::StatusOr<Curve> ReadSegments(const Json& segments, const std::string& path) {
  KOMA_RETURN_IF_ERROR(RequireArray(segments, path));
  const size_t size = segments.size();
  if (size < 3) {  // "Curves can't be empty": a first point alone is not a curve either
    return PathError(path, absl::StrCat("expected the first point (2 numbers) and at least one "
                                        "segment, got ",
                                        size, " number(s)"));
  }
  Curve curve;
  KOMA_ASSIGN_OR_RETURN(curve.start, ReadPoint(segments, 0, path));
  size_t at = 2;  // the first identifier
  while (at < size) {
    CurveSegment segment;
    KOMA_ASSIGN_OR_RETURN(segment.type, ReadSegmentType(segments, at, path));
    const bool bezier = segment.type == SegmentType::kBezier;
    const size_t needed = bezier ? 6 : 2;  // numbers after the identifier
    if (size - at - 1 < needed) {
      return PathError(
          IndexPath(path, at),
          absl::StrCat(segment.type == SegmentType::kInverseStepped ? "an " : "a ",
                       SegmentTypeName(segment.type), " segment needs ", needed,
                       " numbers after its identifier, the array has ", size - at - 1));
    }
    if (bezier) {
      KOMA_ASSIGN_OR_RETURN(segment.handles[0], ReadPoint(segments, at + 1, path));
      KOMA_ASSIGN_OR_RETURN(segment.handles[1], ReadPoint(segments, at + 3, path));
    }
    KOMA_ASSIGN_OR_RETURN(segment.end, ReadPoint(segments, at + needed - 1, path));
    curve.segments.push_back(segment);
    at += 1 + needed;
  }
  return curve;
}

}  // namespace koma::formats::motion3_internal
