// Small valid LipBlink requests for the server tests.
#ifndef KOMA_TESTS_SERVER_LIP_BLINK_REQUEST_BUILDER_H_
#define KOMA_TESTS_SERVER_LIP_BLINK_REQUEST_BUILDER_H_

#include "koma/v1/retime.pb.h"

namespace koma::testing {

// 60 frames at 30 fps: "ParamMouthOpenY" talks over frames 10-39 (a zigzag 0..1), two eyes
// blink at frames 20-27 (right one a frame later), "ParamAngleX" turns slowly.
inline v1::LipBlinkRequest MakeLipBlinkRequest() {
  v1::LipBlinkRequest request;
  v1::CurveSet* set = request.mutable_curves();
  set->set_fps(30.0);
  set->set_frame_count(60);
  v1::Curve* mouth = set->add_curves();
  mouth->set_id("ParamMouthOpenY");
  for (int f = 0; f < 60; ++f) {
    mouth->add_samples(f >= 10 && f < 40 ? 0.25 * ((f * 7) % 5) : 0.0);
  }
  for (int eye = 0; eye < 2; ++eye) {
    v1::Curve* curve = set->add_curves();
    curve->set_id(eye == 0 ? "ParamEyeLOpen" : "ParamEyeROpen");
    const double shape[] = {1, 0.6, 0.2, 0, 0, 0.3, 0.6, 0.85, 1};  // frames 20..28
    for (int f = 0; f < 60; ++f) {
      const int i = f - 20 - eye;
      curve->add_samples(i >= 0 && i < 9 ? shape[i] : 1.0);
    }
  }
  v1::Curve* angle = set->add_curves();
  angle->set_id("ParamAngleX");
  for (int f = 0; f < 60; ++f) angle->add_samples(0.1 * f);
  return request;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_SERVER_LIP_BLINK_REQUEST_BUILDER_H_
