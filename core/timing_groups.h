// Timing groups of RetimeCurves (docs/semantics.md, "Timing groups"), as Cubism's per-group
// Frame Step: curves put in groups by id patterns, each group with its own key poses (from its
// own curves), frames per drawing and spacing, so hair can be on twos while the body is on
// threes. Curves no group matches form the default group, timed with the request's top-level
// options.
#ifndef KOMA_CORE_TIMING_GROUPS_H_
#define KOMA_CORE_TIMING_GROUPS_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/string_view.h"

namespace koma {

// What RetimeCurves does with a group's curves (docs/semantics.md, "Group modes").
enum class TimingGroupMode : uint8_t {
  kStep,      // koma-uchi on the group's key poses, n and spacing
  kKeep,      // the curves as they came in: the input at every frame, no steps, timing -1
  // Stepped here as kStep; the caller (server/curves_lip_blink.h) then redraws the group's
  // mouth and eye curves with LipBlink.
  kLipBlink,
};

struct CurveTimingGroup {
  std::string name;  // unique, non-empty; names the group in the answer, reports and sheets
  // Curve ids or patterns ('*' any run of characters, '?' one character). A curve belongs to
  // the first group with a pattern matching its id.
  std::vector<std::string> ids;
  std::optional<int> frames_per_drawing;  // n; unset: the request's
  std::optional<double> tame;             // s_a; unset: the request's
  std::optional<double> tsume;            // s_b; unset: the request's
  // The group's named key poses in frames; empty: its own curves' keyframes (merged into poses
  // unless the request turns merging off).
  std::vector<int> key_frames;
  TimingGroupMode mode = TimingGroupMode::kStep;
};

// The name of the group of curves no group matches (the request's top-level options).
inline constexpr absl::string_view kDefaultTimingGroupName = "body";

// '*' matches any run of characters (also none), '?' exactly one; everything else itself.
// Case-sensitive, as Live2D ids are. Linear time in practice (greedy with one backtrack point).
bool IdMatches(absl::string_view pattern, absl::string_view id);

// Per id: the index of the first group matching it, or groups.size() for the default group.
int GroupOf(const std::vector<CurveTimingGroup>& groups, absl::string_view id);

// The default grouping of Live2D's standard parameter ids (docs.live2d.com, "Standard
// Parameter List"), in this order:
//   "face": ParamEye*, ParamBrow*, ParamMouth*, ParamCheek (eyes, eyeballs, brows, mouth,
//           blush: keyed on their own, blinks anywhere);
//   "hair": ParamHair*, ParamBust*, ParamSkirt*, ParamRibbon* (what physics usually drives).
// Everything else (ParamAngle*, ParamBody*, ParamArm*, ParamHand*, ParamShoulder*,
// ParamBreath, ParamBase*, custom ids) is the default group, "body". Each group takes the
// request's n and spacing and its own key poses; "face" is kLipBlink (LipBlink draws its
// ParamMouthOpenY, ParamEyeLOpen and ParamEyeROpen, the rest is stepped), "hair" kStep.
std::vector<CurveTimingGroup> DefaultLive2dTimingGroups();

}  // namespace koma

#endif  // KOMA_CORE_TIMING_GROUPS_H_
