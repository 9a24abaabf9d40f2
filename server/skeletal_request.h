// RetimeSkeletal: proto request -> validated core inputs -> core algorithm -> proto response.
#ifndef KOMA_SERVER_SKELETAL_REQUEST_H_
#define KOMA_SERVER_SKELETAL_REQUEST_H_

#include <grpcpp/support/slice.h>

#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/distance.h"
#include "core/film_grid.h"
#include "core/retime.h"
#include "core/retime_shots.h"
#include "core/skeleton.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"

namespace koma::server {

// The anime defaults of a request that names none of the paper's counts (omissions, holds,
// max_hold): on threes with about one snap a second, scaling with the take's length
// (docs/semantics.md, "Defaults: anime timing", measured on real takes at 30-120 fps).
inline constexpr double kDefaultOmissionsPerSecond = 1.0;  // per second of counted time
inline constexpr double kDefaultDrawingsPerSecond = 8.0;   // on threes on the 24 fps grid

// Everything the core needs, checked. Channel values stay in the request message.
struct SkeletalJob {
  Skeleton skeleton;
  int frame_count = 0;
  bool channel_form = true;  // false: the request carried world positions
  DistanceOptions distance_options;
  RetimeOptions retime_options;  // counts in grid frames when `grid` is set
  bool return_motion = true;
  // The film grid drawings are counted on; unset: count in source frames.
  std::optional<FilmGrid> grid;
  bool output_at_timing_rate = false;  // with a grid: write the motion at the grid's rate
  // Cuts and shots (docs/semantics.md, "Cuts and shots"): the rule, and how the whole clip's
  // counts become each shot's. retime_options already holds the drawing target and the hold
  // bound of a drawing rate for the whole clip.
  CutRule cut_rule;
  double drawings_per_frame = 0.0;   // drawings_per_second / counted fps; 0: no rate
  bool holds_per_frame_cap = false;  // drawings_per_second given, holds not
  // The rates used after the anime defaults, per second of counted time; 0: none.
  double omissions_per_second = 0.0;
  double drawings_per_second = 0.0;
  // The request's given_timing (docs/semantics.md, "A given timing"), validated: per counted
  // frame, the source frame it shows. Set: no distance is measured and nothing is chosen.
  std::optional<std::vector<int32_t>> given_source_frames;
};

// Checks every field and returns INVALID_ARGUMENT, OUT_OF_RANGE or RESOURCE_EXHAUSTED with
// the field path and value on the first problem. No algorithm work happens here.
absl::StatusOr<SkeletalJob> ValidateSkeletalRequest(const v1::RetimeSkeletalRequest& request,
                                                    const RequestLimits& limits);

// What a RetimeSkeletal call answers: the response's wire bytes (server/skeletal_response.h).
struct SkeletalAnswer {
  grpc::Slice bytes;
  int frames = 0;  // of a file request's clip, for the call's log line and metrics
  int joints = 0;
  std::vector<std::string> warnings;  // where the file bent a rule, for the log line
};

// Validates, runs forward kinematics (channel form) and RetimeFast, and encodes the response
// into `answer`, the returned motion's frames copied from `request` straight into the bytes.
// RESOURCE_EXHAUSTED if the response would pass protobuf's 2 GiB limit.
absl::Status RetimeSkeletalAnswer(const v1::RetimeSkeletalRequest& request,
                                  const RequestLimits& limits, SkeletalAnswer* answer);

// The same answer as a RetimeSkeletalResponse message: the reference the wire encoder is tested
// against, and the response of the typed-API benchmark servers.
absl::Status HandleRetimeSkeletal(const v1::RetimeSkeletalRequest& request,
                                  const RequestLimits& limits,
                                  v1::RetimeSkeletalResponse* response);

}  // namespace koma::server

#endif  // KOMA_SERVER_SKELETAL_REQUEST_H_
