// Small valid RetimeCurves requests for the server tests.
#ifndef KOMA_TESTS_SERVER_CURVES_REQUEST_BUILDER_H_
#define KOMA_TESTS_SERVER_CURVES_REQUEST_BUILDER_H_

#include "koma/v1/retime.pb.h"

namespace koma::testing {

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
