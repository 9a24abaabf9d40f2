#include "server/curves_lip_blink.h"

#include <optional>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "convert/field_error.h"
#include "core/lip_blink_grid.h"
#include "core/status_macros.h"

namespace koma::server {
namespace {

using convert::Prefixed;

bool HasLipBlinkFields(const v1::CurveTimingGroup& group) {
  return group.has_mouth() || group.has_eyes() || group.has_seed();
}

// The group's curves alone, as a set of their own (LipBlink resolves ids among them).
CurveSet GroupSet(const CurveSet& set, const std::vector<int>& members) {
  CurveSet out;
  out.fps = set.fps;
  out.frame_count = set.frame_count;
  out.beziers_restricted = set.beziers_restricted;
  out.curves.reserve(members.size());
  for (int c : members) out.curves.push_back(set.curves[c]);
  return out;
}

}  // namespace

absl::StatusOr<std::vector<GroupLipBlink>> PrepareGroupLipBlinks(
    const v1::RetimeCurvesRequest& request, const CurveSet& set, const KomaUchiOptions& options,
    const RequestLimits& limits) {
  for (int g = 0; g < request.timing_groups_size(); ++g) {
    const v1::CurveTimingGroup& group = request.timing_groups(g);
    if (group.mode() != v1::GROUP_LIP_BLINK && HasLipBlinkFields(group)) {
      return absl::InvalidArgumentError(
          absl::StrCat("timing_groups[", g, "]: mouth, eyes and seed are for mode "
                       "GROUP_LIP_BLINK, and the mode is ",
                       v1::CurveTimingGroupMode_Name(group.mode())));
    }
  }
  std::vector<GroupLipBlink> jobs;
  std::vector<std::vector<int>> members;  // made once, when some group draws with LipBlink
  for (size_t g = 0; g < options.groups.size(); ++g) {
    const CurveTimingGroup& group = options.groups[g];
    if (group.mode != TimingGroupMode::kLipBlink) continue;
    if (members.empty()) members = GroupMembers(options, set);
    // The request's settings for its own groups; the default grouping's take LipBlink's.
    const bool given = static_cast<int>(g) < request.timing_groups_size();
    const v1::CurveTimingGroup& in =
        given ? request.timing_groups(static_cast<int>(g)) : v1::CurveTimingGroup::default_instance();
    v1::MouthSettings mouth = in.mouth();
    // The mouth flaps at the group's n unless told otherwise: on twos with the rest on twos.
    if (!mouth.has_frames_per_shape()) {
      mouth.set_frames_per_shape(group.frames_per_drawing.value_or(options.frames_per_drawing));
    }
    GroupLipBlink job;
    job.set_index = members[g];
    absl::StatusOr<LipBlinkJob> made = LipBlinkJobFor(
        GroupSet(set, members[g]), mouth, in.eyes(),
        in.has_seed() ? std::optional<uint64_t>(in.seed()) : std::nullopt,
        options.timing_fps, limits, /*need_curves=*/false,
        absl::StrCat("timing group \"", group.name, "\""));
    if (!made.ok()) return Prefixed(made.status(), absl::StrCat("timing_groups[", g, "]."));
    job.job = *std::move(made);
    if (job.job.mouth_curves.empty() && job.job.eye_curves.empty()) continue;  // all stepped
    jobs.push_back(std::move(job));
  }
  return jobs;
}

absl::Status DrawGroupLipBlinks(const std::vector<GroupLipBlink>& jobs, KomaUchiResult& result) {
  for (const GroupLipBlink& group : jobs) {
    const LipBlinkJob& job = group.job;
    KOMA_ASSIGN_OR_RETURN(const LipBlinkDrawing drawing, DrawLipBlink(job));
    for (const LipBlinkDrawnCurve& drawn : drawing.curves) {
      RetimedCurve& out = result.curves[group.set_index[drawn.index]];
      const std::vector<double>& tau = result.timings[out.timing].source_frame;
      const std::vector<bool> repainted =
          job.grid ? RepaintedSourceFrames(drawn.repainted, *job.grid, job.set.frame_count)
                   : drawn.repainted;
      std::vector<double> held = HeldBetweenRepaints(drawn.source, tau, repainted);
      if (job.grid) {
        SourceRateCurve expanded = ExpandConverted(drawn.drawn, drawn.repainted, held, *job.grid);
        out.values = std::move(expanded.values);
        out.steps = std::move(expanded.steps);
      } else {
        for (size_t k = 0; k < held.size(); ++k) {
          if (repainted[k]) held[k] = drawn.drawn[k];
        }
        out.steps = SteppedFromValues(held);
        out.values = std::move(held);
      }
      out.hold_histogram.clear();
      out.keys.clear();  // LipBlink draws these curves, not the key rule
    }
  }
  return absl::OkStatus();
}

}  // namespace koma::server
