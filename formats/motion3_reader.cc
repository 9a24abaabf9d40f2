// ParseMotion3 and CountMotion3: nlohmann parses the text into an ordered_json document (kept
// whole in Motion3File), then the fields koma uses are checked and converted to frames.
#include <climits>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "formats/json_text.h"
#include "formats/motion3.h"
#include "formats/motion3_internal.h"
#include "formats/number_format.h"
#include "formats/text_encoding.h"

namespace koma::formats {
namespace {

using motion3_internal::CurveEntry;
using motion3_internal::DescribeJson;
using motion3_internal::FindMember;
using motion3_internal::Json;
using motion3_internal::NumberAt;
using motion3_internal::PathError;
using motion3_internal::ReadCurveEntry;
using motion3_internal::RequireArray;
using motion3_internal::RequireMember;
using motion3_internal::RequireObject;
using motion3_internal::StringAt;

// t x fps, snapped to an integer within kFrameSnap (frames).
double SecondsToFrames(double seconds, double fps) {
  const double frames = seconds * fps;
  const double nearest = std::round(frames);
  return std::fabs(frames - nearest) <= kFrameSnap ? nearest + 0.0 : frames;  // +0.0: no -0
}

void ConvertToFrames(double fps, Curve& curve) {
  curve.start.frame = SecondsToFrames(curve.start.frame, fps);
  for (CurveSegment& segment : curve.segments) {
    for (CurvePoint& handle : segment.handles) handle.frame = SecondsToFrames(handle.frame, fps);
    segment.end.frame = SecondsToFrames(segment.end.frame, fps);
  }
  // Non-Bezier handles stay {0, 0}: ReadSegments leaves them default.
}

// Meta.Fps, Meta.Duration and Meta.AreBeziersRestricted into `set`.
absl::Status ReadMeta(const Json& document, CurveSet& set) {
  KOMA_ASSIGN_OR_RETURN(const Json* meta, RequireMember(document, "", "Meta"));
  KOMA_RETURN_IF_ERROR(RequireObject(*meta, "Meta"));
  KOMA_ASSIGN_OR_RETURN(const Json* fps_json, RequireMember(*meta, "Meta", "Fps"));
  KOMA_ASSIGN_OR_RETURN(set.fps, NumberAt(*fps_json, "Meta.Fps"));
  if (!(set.fps > 0.0)) {
    return PathError("Meta.Fps",
                     absl::StrCat("expected a number > 0, got ", FormatDouble(set.fps)));
  }
  KOMA_ASSIGN_OR_RETURN(const Json* duration_json, RequireMember(*meta, "Meta", "Duration"));
  KOMA_ASSIGN_OR_RETURN(const double duration, NumberAt(*duration_json, "Meta.Duration"));
  if (duration < 0.0) {
    return PathError("Meta.Duration", absl::StrCat("expected a number >= 0 (seconds), got ",
                                                   FormatDouble(duration)));
  }
  const double last_frame = std::round(duration * set.fps);
  if (!(last_frame < static_cast<double>(INT_MAX))) {
    return absl::OutOfRangeError(absl::StrCat("Meta.Duration x Meta.Fps: ", FormatDouble(duration),
                                              " s x ", FormatDouble(set.fps),
                                              " fps is more frames than an int holds"));
  }
  set.frame_count = static_cast<int>(last_frame) + 1;
  set.beziers_restricted = false;  // the Cubism SDK's default, see motion3.h
  const Json* restricted = FindMember(*meta, "AreBeziersRestricted");
  if (restricted != nullptr) {
    if (!restricted->is_boolean()) {
      return PathError("Meta.AreBeziersRestricted",
                       absl::StrCat("expected true or false, got ", DescribeJson(*restricted)));
    }
    set.beziers_restricted = restricted->get<bool>();
  }
  return absl::OkStatus();
}

absl::Status CheckTopLevel(const Json& document) {
  if (document.is_object()) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrCat("expected a JSON object at the top level, got ", DescribeJson(document)));
}

absl::StatusOr<const Json*> RequireCurves(const Json& document) {
  KOMA_RETURN_IF_ERROR(CheckTopLevel(document));
  KOMA_ASSIGN_OR_RETURN(const Json* curves, RequireMember(document, "", "Curves"));
  KOMA_RETURN_IF_ERROR(RequireArray(*curves, "Curves"));
  if (curves->size() > static_cast<size_t>(INT_MAX)) {
    return absl::OutOfRangeError(absl::StrCat("Curves: ", curves->size(), " curves"));
  }
  return curves;
}

// Adds UserData's entry count and Value bytes to `counts`.
absl::Status CountUserData(const Json& document, Motion3Counts& counts) {
  const Json* user_data = FindMember(document, "UserData");
  if (user_data == nullptr) return absl::OkStatus();
  KOMA_RETURN_IF_ERROR(RequireArray(*user_data, "UserData"));
  size_t bytes = 0;
  for (size_t i = 0; i < user_data->size(); ++i) {
    const std::string path = absl::StrCat("UserData[", i, "]");
    const Json& entry = (*user_data)[i];
    KOMA_RETURN_IF_ERROR(RequireObject(entry, path));
    KOMA_ASSIGN_OR_RETURN(const Json* time, RequireMember(entry, path, "Time"));
    KOMA_RETURN_IF_ERROR(NumberAt(*time, path + ".Time").status());
    KOMA_ASSIGN_OR_RETURN(const Json* value, RequireMember(entry, path, "Value"));
    KOMA_ASSIGN_OR_RETURN(const std::string text, StringAt(*value, path + ".Value"));
    bytes += text.size();  // nlohmann keeps strings as UTF-8
  }
  if (bytes > static_cast<size_t>(INT_MAX) || user_data->size() > static_cast<size_t>(INT_MAX)) {
    return absl::OutOfRangeError(absl::StrCat("UserData: ", bytes, " bytes of values"));
  }
  counts.user_data_count = static_cast<int>(user_data->size());
  counts.total_user_data_size = static_cast<int>(bytes);
  return absl::OkStatus();
}

}  // namespace

bool operator==(const Motion3Counts& a, const Motion3Counts& b) {
  return a.curve_count == b.curve_count && a.total_segment_count == b.total_segment_count &&
         a.total_point_count == b.total_point_count && a.user_data_count == b.user_data_count &&
         a.total_user_data_size == b.total_user_data_size;
}
bool operator!=(const Motion3Counts& a, const Motion3Counts& b) { return !(a == b); }

absl::StatusOr<Motion3File> ParseMotion3(std::string_view text) {
  // UTF-16 is refused by name. A UTF-8 byte order mark needs no skipping: nlohmann's lexer
  // skips it itself, and its error offsets then count bytes from the file's start.
  KOMA_RETURN_IF_ERROR(SkipUtf8Bom(text).status());
  Motion3File file;
  KOMA_ASSIGN_OR_RETURN(file.document, ParseJsonTextWithin(text, kMaxMotion3Depth));
  KOMA_RETURN_IF_ERROR(CheckTopLevel(file.document));
  KOMA_RETURN_IF_ERROR(ReadMeta(file.document, file.curves));
  KOMA_ASSIGN_OR_RETURN(const Json* curves, RequireCurves(file.document));
  for (size_t i = 0; i < curves->size(); ++i) {
    KOMA_ASSIGN_OR_RETURN(CurveEntry entry, ReadCurveEntry((*curves)[i], static_cast<int>(i)));
    ConvertToFrames(file.curves.fps, entry.curve);
    file.curves.curves.push_back(std::move(entry.curve));
    file.targets.push_back(std::move(entry.target));
  }
  // UserData is not converted, but a broken one is reported now rather than when writing.
  Motion3Counts unused;
  KOMA_RETURN_IF_ERROR(CountUserData(file.document, unused));
  return file;
}

absl::StatusOr<Motion3Counts> CountMotion3(const nlohmann::ordered_json& document) {
  KOMA_ASSIGN_OR_RETURN(const Json* curves, RequireCurves(document));
  Motion3Counts counts;
  counts.curve_count = static_cast<int>(curves->size());
  size_t segments = 0;
  size_t points = 0;
  for (size_t i = 0; i < curves->size(); ++i) {
    KOMA_ASSIGN_OR_RETURN(const CurveEntry entry,
                          ReadCurveEntry((*curves)[i], static_cast<int>(i)));
    segments += entry.curve.segments.size();
    points += 1;  // the first point
    for (const CurveSegment& segment : entry.curve.segments) {
      points += segment.type == SegmentType::kBezier ? 3 : 1;
    }
  }
  if (points > static_cast<size_t>(INT_MAX)) {
    return absl::OutOfRangeError(absl::StrCat("Curves: ", points, " points"));
  }
  counts.total_segment_count = static_cast<int>(segments);
  counts.total_point_count = static_cast<int>(points);
  KOMA_RETURN_IF_ERROR(CountUserData(document, counts));
  return counts;
}

}  // namespace koma::formats
