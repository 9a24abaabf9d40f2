#include "bench/echo_shapes.h"

#include <algorithm>
#include <functional>

#include "absl/strings/match.h"

namespace koma::echo {
namespace {

// Stepped points carry a non-zero value: proto3 leaves a 0.0 out of the wire, koma's values
// are rarely exactly 0.
constexpr double kPointValue = 0.5;
constexpr int kMouthHoldFrames = 3;
constexpr double kShutBelow = 0.5;

// motion3's stepped form: the first point is the start, each next one ends a stepped segment.
void AddSteppedPoint(int frame, v1::Curve* stepped) {
  v1::CurvePoint* point = stepped->mutable_start();
  if (stepped->has_start()) {
    v1::CurveSegment* segment = stepped->add_segments();
    segment->set_type(v1::SEGMENT_STEPPED);
    point = segment->mutable_end();
  }
  point->set_frame(frame);
  point->set_value(kPointValue);
}

// Calls visit(begin, end) for each maximal run of samples where `inside` holds.
void ForEachRun(const v1::Curve& curve, const std::function<bool(double)>& inside,
                const std::function<void(int, int)>& visit) {
  const auto& samples = curve.samples();
  int begin = -1;
  for (int f = 0; f <= samples.size(); ++f) {
    const bool in = f < samples.size() && inside(samples[f]);
    if (in && begin < 0) begin = f;
    if (!in && begin >= 0) {
      visit(begin, f);
      begin = -1;
    }
  }
}

}  // namespace

void SkeletalLookalike(const v1::RetimeSkeletalRequest& request,
                       v1::RetimeSkeletalResponse* response) {
  const int frames = std::max(0, request.motion().frame_count());
  for (int f = 0; f < frames; ++f) {
    response->add_source_frames(f);
    response->add_kinds(v1::ORIGINAL);
  }
  response->mutable_input_ssd()->Resize(frames, 0.0);
  *response->mutable_motion() = request.motion();
}

void CurvesLookalike(const v1::RetimeCurvesRequest& request, v1::RetimeCurvesResponse* response) {
  const int frames = std::max(0, request.curves().frame_count());
  const int n = request.has_frames_per_drawing() ? std::max(1, request.frames_per_drawing()) : 3;
  const int drawings = (frames + n - 1) / n;
  if (request.curves().curves_size() > 0) {
    const v1::Curve& first = request.curves().curves(0);
    response->add_key_frames(static_cast<int>(first.start().frame()));
    for (const v1::CurveSegment& segment : first.segments()) {
      response->add_key_frames(static_cast<int>(segment.end().frame()));
    }
  }
  v1::DrawingTiming* timing = response->add_timings();
  timing->set_frames_per_drawing(n);
  for (int f = 0; f < frames; ++f) {
    timing->add_drawing_of_frame(f / n);
    timing->add_source_frame(f - f % n);
  }
  for (int d = 0; d < drawings; ++d) timing->add_drawing_start(d * n);
  for (const v1::Curve& curve : request.curves().curves()) {
    v1::RetimedCurve* out = response->add_curves();
    out->set_id(curve.id());
    out->mutable_values()->Resize(frames, 0.0);
    out->mutable_stepped()->set_id(curve.id());
    for (int d = 0; d < drawings; ++d) AddSteppedPoint(d * n, out->mutable_stepped());
    v1::HoldCount* holds = out->add_hold_histogram();
    holds->set_length(n);
    holds->set_drawings(drawings);
  }
}

void LipBlinkLookalike(const v1::LipBlinkRequest& request, v1::LipBlinkResponse* response) {
  const int frames = std::max(0, request.curves().frame_count());
  for (const v1::Curve& curve : request.curves().curves()) {
    const bool mouth = absl::StrContains(curve.id(), "Mouth");
    if (!mouth && !absl::StrContains(curve.id(), "Eye")) continue;
    v1::ConvertedCurve* out = response->add_curves();
    out->set_id(curve.id());
    out->mutable_values()->Resize(frames, 0.0);
    v1::Curve* stepped = out->mutable_stepped();
    stepped->set_id(curve.id());
    AddSteppedPoint(0, stepped);
    if (mouth) {
      v1::MouthTrack* track = response->add_mouths();
      track->set_id(curve.id());
      ForEachRun(
          curve, [](double v) { return v != 0.0; },
          [&](int begin, int end) {
            v1::FrameInterval* speech = track->add_speech();
            speech->set_begin(begin);
            speech->set_end(end);
            for (int f = begin; f < end; f += kMouthHoldFrames) {
              v1::MouthHold* hold = track->add_holds();
              hold->set_begin(f);
              hold->set_length(std::min(kMouthHoldFrames, end - f));
              hold->set_shape(f % 2 ? v1::MOUTH_OPEN : v1::MOUTH_MID);
              AddSteppedPoint(f, stepped);
            }
            AddSteppedPoint(end, stepped);
          });
      track->set_closed_level(kPointValue);
      track->set_mid_level(kPointValue);
      track->set_open_level(kPointValue);
    } else {
      v1::EyeTrack* track = response->add_eyes();
      track->set_id(curve.id());
      ForEachRun(
          curve, [](double v) { return v < kShutBelow; },
          [&](int begin, int end) {
            v1::Blink* blink = track->add_blinks();
            blink->set_closing_begin(begin);
            blink->set_closed_begin(begin);
            blink->set_closed_end(end - 1);
            blink->set_open_span(end - begin);
            blink->set_hold(2);
            AddSteppedPoint(begin, stepped);
            AddSteppedPoint(end, stepped);
          });
      track->set_closed_level(kPointValue);
      track->set_mid_level(kPointValue);
      track->set_open_level(kPointValue);
    }
  }
  response->set_seed(request.has_seed() ? request.seed() : 0x6b6f6d61);
}

}  // namespace koma::echo
