// WriteMotion3: a copy of the parsed document with some Segments replaced by stepped keyframes
// and the Meta counts recomputed, dumped by nlohmann.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "formats/json_text.h"
#include "formats/motion3.h"
#include "formats/motion3_internal.h"
#include "formats/number_format.h"

namespace koma::formats {
namespace {

using motion3_internal::Json;
using motion3_internal::PathError;
using motion3_internal::RequireMember;
using motion3_internal::RequireObject;

absl::Status CheckSteps(const std::vector<CurvePoint>& steps, const std::string& path) {
  if (steps.size() < 2) {
    return PathError(path,
                     absl::StrCat("expected at least 2 stepped keyframes, got ", steps.size()));
  }
  for (size_t k = 0; k < steps.size(); ++k) {
    const std::string here = absl::StrCat(path, "[", k, "]");
    if (!std::isfinite(steps[k].frame) || !std::isfinite(steps[k].value)) {
      return PathError(
          here, absl::StrCat("expected finite numbers, got frame ", FormatDouble(steps[k].frame),
                             ", value ", FormatDouble(steps[k].value)));
    }
    if (k > 0 && !(steps[k].frame > steps[k - 1].frame)) {
      return PathError(here + ".frame", absl::StrCat(FormatDouble(steps[k].frame),
                                                     " is not after the previous keyframe's frame ",
                                                     FormatDouble(steps[k - 1].frame)));
    }
  }
  return absl::OkStatus();
}

// [t0, v0, 2, t1, v1, 2, t2, v2, ...] with t = frame / fps (seconds).
Json SteppedSegments(const std::vector<CurvePoint>& steps, double fps) {
  Json segments = Json::array();
  for (size_t k = 0; k < steps.size(); ++k) {
    if (k > 0) segments.push_back(static_cast<int>(SegmentType::kStepped));
    segments.push_back(JsonNumber(steps[k].frame / fps));
    segments.push_back(JsonNumber(steps[k].value));
  }
  return segments;
}

// Sets Meta's count fields, in place when present, appended otherwise.
absl::Status SetCounts(Json& document) {
  KOMA_ASSIGN_OR_RETURN(const Motion3Counts counts, CountMotion3(document));
  KOMA_ASSIGN_OR_RETURN(const Json* meta_in, RequireMember(document, "", "Meta"));
  KOMA_RETURN_IF_ERROR(RequireObject(*meta_in, "Meta"));
  Json& meta = document["Meta"];
  meta["CurveCount"] = counts.curve_count;
  meta["TotalSegmentCount"] = counts.total_segment_count;
  meta["TotalPointCount"] = counts.total_point_count;
  meta["UserDataCount"] = counts.user_data_count;
  meta["TotalUserDataSize"] = counts.total_user_data_size;
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<std::string> WriteMotion3(
    const Motion3File& original,
    const std::vector<std::optional<std::vector<CurvePoint>>>& stepped) {
  // Checks Curves before indexing into it.
  KOMA_RETURN_IF_ERROR(CountMotion3(original.document).status());
  const size_t curve_count = original.document.at("Curves").size();
  if (stepped.size() != curve_count) {
    return absl::InvalidArgumentError(absl::StrCat("stepped: expected one entry per curve (",
                                                   curve_count, "), got ", stepped.size()));
  }
  const double fps = original.curves.fps;
  if (!std::isfinite(fps) || !(fps > 0.0)) {
    return PathError("curves.fps", absl::StrCat("expected a number > 0, got ", FormatDouble(fps)));
  }
  Json document = original.document;
  for (size_t i = 0; i < curve_count; ++i) {
    if (!stepped[i].has_value()) continue;
    KOMA_RETURN_IF_ERROR(CheckSteps(*stepped[i], absl::StrCat("stepped[", i, "]")));
    document["Curves"][i]["Segments"] = SteppedSegments(*stepped[i], fps);
  }
  KOMA_RETURN_IF_ERROR(SetCounts(document));
  // error_handler_t::replace: never throw on invalid UTF-8 (a parsed document has none).
  std::string text = document.dump(1, '\t', /*ensure_ascii=*/false, Json::error_handler_t::replace);
  text += '\n';
  return text;
}

}  // namespace koma::formats
