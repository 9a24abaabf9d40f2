// LipBlink: proto request -> validated core inputs -> mouth and eye conversion -> response.
#ifndef KOMA_SERVER_LIP_BLINK_REQUEST_H_
#define KOMA_SERVER_LIP_BLINK_REQUEST_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/curves.h"
#include "core/film_grid.h"
#include "core/lip_blink.h"
#include "core/voice_activity.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"

namespace koma::server {

// The seed of an unseeded request: "koma" in ASCII.
inline constexpr uint64_t kDefaultLipBlinkSeed = 0x6b6f6d61;

struct LipBlinkJob {
  CurveSet set;
  std::vector<int> mouth_curves;  // indices into set.curves
  std::vector<int> eye_curves;
  MouthOptions mouth;
  EyeOptions eyes;
  uint64_t seed = kDefaultLipBlinkSeed;
  // The film grid holds are counted on; unset: source frames. With a grid, `mouth` and
  // `eyes` are for the grid's frames (intervals snapped, auto-blink fps = the grid's).
  std::optional<FilmGrid> grid;
  int grid_frames = 0;
  // A voice request (server/lip_blink_voice.h): the speech and the drawing each frame asks
  // for, on the frames holds count (grid frames, else source frames). The mouth curves'
  // inputs are then these drawings' levels, and their source values the closed level.
  std::optional<VoiceActivity> voice;
  // A given timing (LipBlinkRequest.given_timing, docs/semantics.md, "A given timing"), on the
  // frames holds count: per mouth curve (mouth_curves' order) its holds, per eye curve
  // (eye_curves' order) its blinks. Unset: computed.
  std::optional<std::vector<std::vector<MouthHold>>> given_mouths;
  std::optional<std::vector<std::vector<Blink>>> given_eyes;
};

// A job on `set` with these settings (the fields of a LipBlinkRequest, or of a GROUP_LIP_BLINK
// timing group; paths in errors as in LipBlinkRequest: "mouth.ids[0]", "timing_fps"). With
// need_curves false a set without mouth or eye curves is a job that draws nothing. An id not
// in the set is "not a curve of <set_name>".
absl::StatusOr<LipBlinkJob> LipBlinkJobFor(CurveSet set, const v1::MouthSettings& mouth,
                                           const v1::EyeSettings& eyes,
                                           std::optional<uint64_t> seed,
                                           std::optional<double> timing_fps,
                                           const RequestLimits& limits, bool need_curves,
                                           absl::string_view set_name);

// MouthSettings and EyeSettings as core options for curves of `frame_count` frames (eyes at
// `fps`), checked; errors name "mouth.<field>" / "eyes.<field>". The ids are not looked at.
absl::StatusOr<MouthOptions> MouthOptionsFromProto(const v1::MouthSettings& in, int frame_count);
absl::StatusOr<EyeOptions> EyeOptionsFromProto(const v1::EyeSettings& in, double fps, int frame_count);

// Every field checked before any work; INVALID_ARGUMENT / RESOURCE_EXHAUSTED naming the
// field path ("mouth.mid_ratio", "eyes.auto_blink.hold", "mouth.ids[1]") and value.
absl::StatusOr<LipBlinkJob> ValidateLipBlinkRequest(const v1::LipBlinkRequest& request,
                                                    const RequestLimits& limits);

// One curve LipBlink draws: the conversion's values (per grid frame with a grid, else per
// source frame), the frames it repainted (same frames: speech or blinks), and the input at
// every source frame.
struct LipBlinkDrawnCurve {
  int index = 0;  // into job.set.curves
  std::vector<double> drawn;
  std::vector<bool> repainted;
  std::vector<double> source;
};

// A job's drawings before they become a response: per mouth curve its result, the eyes'
// result, and the drawn curves (mouth curves, then eye curves, in the job's order).
struct LipBlinkDrawing {
  std::vector<MouthResult> mouths;
  EyeResult eyes;
  std::vector<LipBlinkDrawnCurve> curves;
};

// The one LipBlink drawing code, shared by the LipBlink RPC and RetimeCurves' GROUP_LIP_BLINK
// groups (server/curves_lip_blink.h). OUT_OF_RANGE where a curve evaluates to inf or NaN.
absl::StatusOr<LipBlinkDrawing> DrawLipBlink(const LipBlinkJob& job);

// Runs a validated job into `response` (mouths, eyes, curves, seed, timing_fps).
absl::Status RunLipBlinkJob(const LipBlinkJob& job, v1::LipBlinkResponse* response);

// The motion a LipBlink call converted, for its log line and metrics: a file's or a Spine
// skeleton's decoded curves (the slots), or a voice's new motion, as well as decoded curves.
struct LipBlinkMotionShape {
  int frames = 0;  // the motion's frames (its own rate)
  int curves = 0;
};

// Puts the job's motion into `shape` when it is given.
void DescribeMotion(const LipBlinkJob& job, LipBlinkMotionShape* shape);

// The LipBlink RPC, whatever the request carries; `shape` (when given) gets the motion's.
absl::Status HandleLipBlink(const v1::LipBlinkRequest& request, const RequestLimits& limits,
                            v1::LipBlinkResponse* response, LipBlinkMotionShape* shape = nullptr);

}  // namespace koma::server

#endif  // KOMA_SERVER_LIP_BLINK_REQUEST_H_
