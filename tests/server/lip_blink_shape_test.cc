// HandleLipBlink's shape (the call's log line and frame metrics): the motion the call converted,
// whatever carried it: decoded curves, a motion3.json, a Spine skeleton's slots, a voice's new
// motion. Before, a skeleton or a voice alone was logged as "frames=0 curves=0".
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

#include "convert/spine_lip_blink.h"
#include "formats/spine.h"
#include "server/lip_blink_request.h"
#include "tests/formats/test_files.h"
#include "tests/testing/status_matchers.h"

namespace koma::server {
namespace {

LipBlinkMotionShape ShapeOf(const v1::LipBlinkRequest& request, v1::LipBlinkResponse* response) {
  LipBlinkMotionShape shape;
  const absl::Status status = HandleLipBlink(request, RequestLimits{}, response, &shape);
  EXPECT_TRUE(status.ok()) << status;
  return shape;
}

TEST(LipBlinkShapeTest, DecodedCurvesAreTheRequestsOwn) {
  v1::LipBlinkRequest request;
  request.mutable_curves()->set_fps(30);
  request.mutable_curves()->set_frame_count(40);
  for (const char* id : {"ParamMouthOpenY", "ParamEyeLOpen", "ParamAngleX"}) {
    v1::Curve* curve = request.mutable_curves()->add_curves();
    curve->set_id(id);
    for (int f = 0; f < 40; ++f) curve->add_samples(f % 7 / 7.0);
  }
  v1::LipBlinkResponse response;
  const LipBlinkMotionShape shape = ShapeOf(request, &response);
  EXPECT_EQ(shape.frames, 40);
  EXPECT_EQ(shape.curves, 3);
}

TEST(LipBlinkShapeTest, AMotion3FileIsDescribedByItsCurves) {
  // 1.2 s at 30 fps: frames 0..36; three curves, one of them not converted.
  v1::LipBlinkRequest request;
  request.set_motion3_json(R"({"Version": 3, "Meta": {"Duration": 1.2, "Fps": 30}, "Curves": [
    {"Target": "Parameter", "Id": "ParamMouthOpenY", "Segments": [0, 0, 0, 1.2, 1]},
    {"Target": "Parameter", "Id": "ParamEyeLOpen", "Segments": [0, 1, 0, 1.2, 1]},
    {"Target": "Parameter", "Id": "ParamAngleX", "Segments": [0, 0, 0, 1.2, 30]}]})");
  v1::LipBlinkResponse response;
  const LipBlinkMotionShape shape = ShapeOf(request, &response);
  EXPECT_EQ(shape.frames, 37);
  EXPECT_EQ(shape.curves, 3);
}

TEST(LipBlinkShapeTest, ASpineSkeletonIsDescribedByItsSlotsAsCurves) {
  v1::LipBlinkRequest request;
  request.set_spine_json(formats::ReadTestFile(KOMA_SAMPLES_DIR "/hero.json"));
  request.mutable_spine()->set_animation("walk");
  request.mutable_spine()->set_mouth_slot("mouth");
  request.mutable_spine()->add_eye_slots("eyes");
  v1::FrameInterval* speech = request.mutable_mouth()->add_speech();
  speech->set_begin(3);
  speech->set_end(20);
  ASSERT_OK_AND_ASSIGN(const formats::SpineFile file, formats::ParseSpine(request.spine_json()));
  ASSERT_OK_AND_ASSIGN(const convert::SpineLipBlinkSlots slots,
                       convert::SpineLipBlinkSlotsOf(request.spine(), file, false, true,
                                                     convert::ProtoSpineLipBlinkNames()));
  ASSERT_OK_AND_ASSIGN(const v1::LipBlinkRequest decoded,
                       convert::DecodedSpineLipBlinkRequest(request, file, slots));
  ASSERT_GT(decoded.curves().frame_count(), 2);

  v1::LipBlinkResponse response;
  const LipBlinkMotionShape shape = ShapeOf(request, &response);
  EXPECT_EQ(shape.frames, decoded.curves().frame_count());
  EXPECT_EQ(shape.curves, 2);  // the mouth slot and the eye slot
}

TEST(LipBlinkShapeTest, AVoiceAloneIsDescribedByTheMotionWrittenFromIt) {
  // Cues until 2.0 s, a new motion at 30 fps: frames 0..60.
  v1::LipBlinkRequest request;
  request.set_rhubarb_cues("0.00\tX\n0.50\tD\n1.00\tB\n1.50\tX\n2.00\tX\n");
  request.set_voice_motion_fps(30);
  v1::LipBlinkResponse response;
  const LipBlinkMotionShape shape = ShapeOf(request, &response);
  EXPECT_EQ(shape.frames, 61);
  const nlohmann::json written = nlohmann::json::parse(response.motion3_json());
  EXPECT_EQ(shape.curves, static_cast<int>(written["Curves"].size()));
  EXPECT_GE(shape.curves, 1);
}

}  // namespace
}  // namespace koma::server
