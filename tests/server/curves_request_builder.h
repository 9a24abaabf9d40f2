// Small valid RetimeCurves requests for the server tests.
#ifndef KOMA_TESTS_SERVER_CURVES_REQUEST_BUILDER_H_
#define KOMA_TESTS_SERVER_CURVES_REQUEST_BUILDER_H_

#include <algorithm>

#include "core/split_mix64.h"
#include "koma/v1/retime.pb.h"

namespace koma::testing {

inline void SetPoint(double frame, double value, v1::CurvePoint* point) {
  point->set_frame(frame);
  point->set_value(value);
}

// A random keyframe curve over `frames` frames: a start, then keys every `min_step` to
// `max_step` frames, segment types drawn from all four (Beziers with handles inside their
// segment), values in [-30, 30). With zero_one_in > 0 the start and the keys are exactly 0
// one time in zero_one_in (so steps carry +0.0 too); with 0 the generator makes no such draw.
// (curves_golden_test pins the bytes of what this draws from given seeds: keep its sequence.)
inline void AddRandomKeyframes(SplitMix64& rng, int frames, int min_step, int max_step,
                               int zero_one_in, v1::Curve* curve) {
  auto value = [&rng, zero_one_in] {
    if (zero_one_in > 0 && rng.OneIn(zero_one_in)) return 0.0;
    return rng.Unit() * 60.0 - 30.0;
  };
  double frame = 0.0;
  SetPoint(frame, value(), curve->mutable_start());
  while (frame < frames - 1) {
    const double next = std::min<double>(frames - 1, frame + rng.Int(min_step, max_step));
    v1::CurveSegment* segment = curve->add_segments();
    const int type = rng.Int(1, 4);
    segment->set_type(static_cast<v1::SegmentType>(type));
    if (type == v1::SEGMENT_BEZIER) {
      const double third = (next - frame) / 3.0;
      SetPoint(frame + third, rng.Unit() * 60.0 - 30.0, segment->mutable_handle1());
      SetPoint(next - third, rng.Unit() * 60.0 - 30.0, segment->mutable_handle2());
    }
    SetPoint(next, value(), segment->mutable_end());
    frame = next;
  }
}

// Random options for a RetimeCurvesRequest whose curves are set: half the time key poses
// (frames 0 and the last, and each other frame one time in `key_one_in`), then
// frames_per_drawing, tame, tsume and per-curve frames_per_drawing, each present or not.
// Returns the number of key poses given (0: the request keeps the default ones). The draws
// are made in this order; the tests' random requests depend on it.
inline int AddRandomCurvesOptions(SplitMix64& rng, int key_one_in,
                                  v1::RetimeCurvesRequest* request) {
  const v1::CurveSet& set = request->curves();
  const int frames = set.frame_count();
  int key_poses = 0;
  if (rng.OneIn(2)) {
    for (int f = 0; f < frames; ++f) {
      if (f == 0 || f == frames - 1 || rng.OneIn(key_one_in)) {
        request->add_key_frames(f);
        ++key_poses;
      }
    }
  }
  if (rng.OneIn(2)) request->set_frames_per_drawing(rng.Int(1, 5));
  if (rng.OneIn(3)) request->set_tame(1.0 + rng.Unit());
  if (rng.OneIn(3)) request->set_tsume(1.0 + rng.Unit());
  for (const v1::Curve& curve : set.curves()) {
    if (!rng.OneIn(4)) continue;
    v1::CurveOverride* own = request->add_curve_overrides();
    own->set_curve_id(curve.id());
    own->set_frames_per_drawing(rng.Int(1, 6));
  }
  return key_poses;
}

// 31 frames at 30 fps: "ParamAngleX" linear 0 -> 30 over frames 0-10, a Bezier back to 0 at
// frame 30; "ParamArm" dense samples 0, 1, 2, ...
inline v1::RetimeCurvesRequest MakeCurvesRequest() {
  v1::RetimeCurvesRequest request;
  v1::CurveSet* set = request.mutable_curves();
  set->set_fps(30.0);
  set->set_frame_count(31);
  set->set_beziers_restricted(true);
  v1::Curve* angle = set->add_curves();
  angle->set_id("ParamAngleX");
  v1::Curve* keys = angle;
  keys->mutable_start()->set_frame(0.0);
  keys->mutable_start()->set_value(0.0);
  v1::CurveSegment* linear = keys->add_segments();
  linear->set_type(v1::SEGMENT_LINEAR);
  linear->mutable_end()->set_frame(10.0);
  linear->mutable_end()->set_value(30.0);
  v1::CurveSegment* bezier = keys->add_segments();
  bezier->set_type(v1::SEGMENT_BEZIER);
  bezier->mutable_handle1()->set_frame(10.0 + 20.0 / 3.0);
  bezier->mutable_handle1()->set_value(30.0);
  bezier->mutable_handle2()->set_frame(10.0 + 40.0 / 3.0);
  bezier->mutable_handle2()->set_value(0.0);
  bezier->mutable_end()->set_frame(30.0);
  bezier->mutable_end()->set_value(0.0);
  v1::Curve* arm = set->add_curves();
  arm->set_id("ParamArm");
  for (int f = 0; f < 31; ++f) arm->add_samples(f);
  return request;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_SERVER_CURVES_REQUEST_BUILDER_H_
