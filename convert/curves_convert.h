// CurveSet (formats/ and core/ side) <-> koma.v1 curve messages (wire side): the one
// conversion, used by the CLI (requests it sends, responses and reports it reads) and by the
// server (requests it checks, responses it answers).
#ifndef KOMA_CONVERT_CURVES_CONVERT_H_
#define KOMA_CONVERT_CURVES_CONVERT_H_

#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "convert/curve_text.h"
#include "core/curves.h"
#include "core/koma_uchi.h"
#include "koma/v1/motion.pb.h"
#include "koma/v1/retime.pb.h"

namespace koma::convert {

v1::CurveSet CurveSetToProto(const CurveSet& set);

// A request's curve set as the core type, checked: INVALID_ARGUMENT naming the field under
// `path` ("curves") for an unknown segment type, a curve with both keyframes and samples or
// with neither, and whatever core ValidateCurveSet refuses (its message after "curves.").
// Size limits are the server's (server/curve_convert.h), checked before this.
absl::StatusOr<CurveSet> CurveSetFromProto(const v1::CurveSet& proto, absl::string_view path);

// One curve as the core type, with CurveSetFromProto's per-curve checks; `path` names it in
// an error ("curves.curves[2]").
absl::StatusOr<Curve> CurveFromProto(const v1::Curve& proto, absl::string_view path);

// Stepped keyframes: `steps[0]` as the start, then a SEGMENT_STEPPED segment to each next
// (nothing for no steps). The inverse of StepsFromProto.
void SteppedKeyframesToProto(const std::vector<CurvePoint>& steps, v1::Curve* out);

// A response curve's stepped keyframes as points (start, then each segment's end).
std::vector<CurvePoint> StepsFromProto(const v1::Curve& stepped);

// A response curve (RetimedCurve of RetimeCurves, ConvertedCurve of LipBlink) as the curve
// writers take it (convert/curve_text.h): its per-frame values and its stepped keyframes.
CurveReplacement ReplacementFromProto(const v1::RetimedCurve& curve);
CurveReplacement ReplacementFromProto(const v1::ConvertedCurve& curve);

// A response timing as the core type (for the drawing sheet writer).
DrawingTiming TimingFromProto(const v1::DrawingTiming& timing);

// "closed", "mid" or "open" for a MouthShape (the CLI's summaries and the report's strip);
// "unspecified" for any other value.
const char* MouthShapeName(int shape);

// Per drawing of response.timings(timing): the ids of the curves whose keys it draws (their
// KeyDrawing with drawn = true), in the curves' order. Sized to the timing's drawings.
std::vector<std::vector<std::string>> KeysByDrawing(const v1::RetimeCurvesResponse& response,
                                                    int timing);

// A core key role (core/key_drawings.h) as the proto's.
v1::KeyRole KeyRoleToProto(KeyRole role);

// A core key drawing as the proto's.
void KeyDrawingToProto(const KeyDrawing& key, v1::KeyDrawing* out);

// A core timing group mode as the proto's.
v1::CurveTimingGroupMode TimingGroupModeToProto(TimingGroupMode mode);

// The mode of each timing group a request asks for, by name: its timing_groups', or with none
// (and default_timing_groups not false) the default grouping's (core/timing_groups.h).
std::map<std::string, v1::CurveTimingGroupMode> TimingGroupModes(
    const v1::RetimeCurvesRequest& request);

// A mode's name in flags, summaries and reports: "step", "keep", "lipblink".
const char* TimingGroupModeName(v1::CurveTimingGroupMode mode);

}  // namespace koma::convert

#endif  // KOMA_CONVERT_CURVES_CONVERT_H_
