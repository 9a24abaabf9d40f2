// RetimeCurves' GROUP_LIP_BLINK timing groups (docs/semantics.md, "Group modes"): the group's
// mouth and eye curves are drawn by LipBlink, through the LipBlink RPC's own code
// (server/lip_blink_request.h: LipBlinkJobFor, DrawLipBlink), on the group's curves alone; the
// core steps the group as a GROUP_STEP group first, and the drawn curves then show LipBlink's
// drawings where it repaints (speech, blinks) and the group's koma-uchi drawings elsewhere.
#ifndef KOMA_SERVER_CURVES_LIP_BLINK_H_
#define KOMA_SERVER_CURVES_LIP_BLINK_H_

#include <cstddef>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/curves.h"
#include "core/koma_uchi.h"
#include "koma/v1/retime.pb.h"
#include "server/lip_blink_request.h"
#include "server/request_limits.h"

namespace koma::server {

struct GroupLipBlink {
  LipBlinkJob job;             // on the group's curves only, in the request's order
  std::vector<int> set_index;  // job.set.curves[i] is the request's curve set_index[i]
};

// Checks the LipBlink fields of every timing group (mouth, eyes, seed only in
// GROUP_LIP_BLINK groups) and makes a job per GROUP_LIP_BLINK group that has mouth or eye
// curves. INVALID_ARGUMENT naming "timing_groups[g].mouth.ids[0]" and so on. `options` are
// the validated options (their groups are the request's, or the default grouping's).
absl::StatusOr<std::vector<GroupLipBlink>> PrepareGroupLipBlinks(
    const v1::RetimeCurvesRequest& request, const CurveSet& set, const KomaUchiOptions& options,
    const RequestLimits& limits);

// Redraws each job's mouth and eye curves in `result` (RetimeCurves' answer for `set`):
// LipBlink's values where it repaints, elsewhere the group's drawings of the input
// (HeldBetweenRepaints); their hold histograms are emptied. OUT_OF_RANGE where a curve
// evaluates to inf or NaN.
absl::Status DrawGroupLipBlinks(const std::vector<GroupLipBlink>& jobs, KomaUchiResult& result);

}  // namespace koma::server

#endif  // KOMA_SERVER_CURVES_LIP_BLINK_H_
