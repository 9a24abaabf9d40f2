// `koma curves IN -o OUT ...`: motion3.json (or per-frame CSV) in, RetimeCurves, the curves
// drawn on twos/threes with tame/tsume out. The steps are separate functions so other drivers
// (`koma batch`) run them per file:
//   ReadCurveInput (client/curve_files.h) -> BuildCurvesRequest -> (the RPC)
//   -> WriteCurvesOutputs -> CurvesSummaryText / CurvesSummaryJson (client/curves_summary.h).
#ifndef KOMA_CLIENT_CURVES_COMMAND_H_
#define KOMA_CLIENT_CURVES_COMMAND_H_

#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "client/curve_files.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// One --segment-overrides value: "SEG:on=N,tame=S,tsume=S" (any of the three keys;
// frames-per-drawing is a synonym of on).
struct SegmentOverrideFlag {
  int segment = 0;
  std::optional<int> frames_per_drawing;
  std::optional<double> tame;
  std::optional<double> tsume;
};
absl::StatusOr<SegmentOverrideFlag> ParseSegmentOverride(const std::string& text);

// One --group value: "NAME=ID,ID*,...[:on=N,tame=S,tsume=S,keys=F/F/...,mode=M,...]" (a
// timing group: its curves by id or pattern, its own n and spacing, its named key poses, its
// mode and, in mode lipblink, mouth=ID/ID, eyes=ID/ID, mouth-mode=random|follow, seed=N).
struct TimingGroupFlag {
  std::string name;
  std::vector<std::string> ids;
  std::optional<int> frames_per_drawing;
  std::optional<double> tame;
  std::optional<double> tsume;
  std::vector<int> key_frames;
  v1::CurveTimingGroupMode mode = v1::CURVE_TIMING_GROUP_MODE_UNSPECIFIED;  // mode=step|keep|lipblink
  // mode=lipblink only: mouth=ID/ID and eyes=ID/ID (the curves LipBlink draws), mouth-mode=
  // random|follow, seed=N.
  std::vector<std::string> mouth_ids, eye_ids;
  std::string mouth_mode;
  std::optional<uint64_t> seed;
};
absl::StatusOr<TimingGroupFlag> ParseTimingGroup(const std::string& text);

// "step", "keep", "lipblink" (also "lip-blink", "lip_blink") -> the mode; INVALID_ARGUMENT
// naming `flag` otherwise.
absl::StatusOr<v1::CurveTimingGroupMode> ParseGroupMode(const std::string& flag,
                                                        const std::string& text);

struct CurvesArgs : CurveFileArgs {
  std::string timing;                     // drawing sheet CSV to write; empty: none; "-"
  std::optional<int> frames_per_drawing;  // --on / --frames-per-drawing; unset: server's 3
  std::vector<int> keys;                  // --keys / --key-frames; empty: keyframe times
  std::optional<double> tame;             // --tame; unset: 1
  std::optional<double> tsume;            // --tsume; unset: 1
  std::vector<std::string> curve_on;      // --curve-on / --curve-overrides ID=N, repeatable
  std::vector<SegmentOverrideFlag> segment_overrides;  // --segment-overrides, repeatable
  bool timing_only = false;  // --timing-only: write only the drawing sheet
  // --animation: a Spine skeleton's animations to retime, repeatable; empty: every animation
  // with bone keys.
  std::vector<std::string> animations;
  bool merge_key_poses = true;  // --no-merge-keys (false): every keyframe time a key pose
  std::vector<TimingGroupFlag> groups;  // --group, repeatable, in order of precedence
  std::vector<std::string> group_on;    // --group-on NAME=N: a group's n (also face, hair)
  std::vector<std::string> group_mode;  // --group-mode NAME=MODE: a group's mode (also face, hair)
  bool default_groups = true;           // --no-default-groups (false): one group
  // --check-keys: measure the answer against the input's keys (core/key_check.h) and print it.
  bool check_keys = false;
};

// The request for `curves` with every flag of `args` applied. INVALID_ARGUMENT naming the
// flag for a malformed --curve-on.
absl::StatusOr<v1::RetimeCurvesRequest> BuildCurvesRequest(const CurvesArgs& args,
                                                           const CurveSet& curves);

// BuildCurvesRequest(args, input.curves); with --send-file the request carries input.text in
// motion3_json or csv_text (with csv_fps = --fps) instead of curves, for the server to parse.
// A Spine input: its selected animation (input.spine_animation), else the one --animation
// names or the only one with bone keys (client/spine_curves.h); with --send-file spine_json and
// spine_animation.
absl::StatusOr<v1::RetimeCurvesRequest> BuildCurvesFileRequest(const CurvesArgs& args,
                                                               const CurveInput& input);

// Flags that cannot work together (usage errors): -o missing without --timing-only,
// --timing-only without --timing, two outputs on standard output.
absl::Status CheckCurvesFlags(const CurvesArgs& args);

// Writes -o (unless --timing-only) and --timing (when given) from `response`.
absl::Status WriteCurvesOutputs(const CurvesArgs& args, const CurveInput& input,
                                const v1::RetimeCurvesResponse& response);

// Exit code: 0 ok, 1 failure, 2 usage error (messages on stderr).
int RunCurves(const CurvesArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CURVES_COMMAND_H_
