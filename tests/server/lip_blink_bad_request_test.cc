// Every malformed LipBlink request gets INVALID_ARGUMENT (or RESOURCE_EXHAUSTED) with the
// field path and value, through an in-process channel to the real service.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"
#include "tests/server/bad_request_table.h"
#include "tests/server/in_process_server.h"
#include "tests/server/lip_blink_request_builder.h"

namespace koma::server {
namespace {

using ::koma::testing::InProcessServer;
using BadLipBlink = ::koma::testing::BadRequest<v1::LipBlinkRequest>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void AddInterval(google::protobuf::RepeatedPtrField<v1::FrameInterval>* list, int begin,
                 int end) {
  v1::FrameInterval* interval = list->Add();
  interval->set_begin(begin);
  interval->set_end(end);
}

std::vector<BadLipBlink> BadRequests() {
  using C = grpc::StatusCode;
  const C kInvalid = C::INVALID_ARGUMENT;
  return {
      {"NoCurveSet", [](auto& r) { r.clear_curves(); }, kInvalid, "curves: required"},
      {"FpsZero", [](auto& r) { r.mutable_curves()->set_fps(0.0); }, kInvalid,
       "curves.fps: 0"},
      {"SampleNaN", [](auto& r) { r.mutable_curves()->mutable_curves(0)->set_samples(3, kNaN); },
       kInvalid, "curves.curves[0].samples[3]: nan"},
      {"NoMouthOrEyes",
       [](auto& r) {
         auto* curves = r.mutable_curves()->mutable_curves();
         for (int i = 0; i < 3; ++i) curves->Mutable(i)->set_id("Other" + std::to_string(i));
       },
       kInvalid, "no mouth or eye curve"},
      {"UnknownMouthId", [](auto& r) { r.mutable_mouth()->add_ids("ParamMouth"); }, kInvalid,
       "mouth.ids[0]: \"ParamMouth\" is not a curve of the request"},
      {"UnknownEyeId",
       [](auto& r) {
         r.mutable_eyes()->add_ids("ParamEyeLOpen");
         r.mutable_eyes()->add_ids("ParamEyeX");
       },
       kInvalid, "eyes.ids[1]: \"ParamEyeX\" is not a curve of the request"},
      {"MouthAlsoEye",
       [](auto& r) {
         r.mutable_mouth()->add_ids("ParamMouthOpenY");
         r.mutable_eyes()->add_ids("ParamMouthOpenY");
       },
       kInvalid, "eyes.ids[0]: \"ParamMouthOpenY\" is already a mouth or eye curve"},
      {"UnknownMode",
       [](auto& r) { r.mutable_mouth()->set_mode(static_cast<v1::MouthMode>(7)); }, kInvalid,
       "mouth.mode: 7 is not a MouthMode"},
      {"FramesPerShapeZero", [](auto& r) { r.mutable_mouth()->set_frames_per_shape(0); },
       kInvalid, "mouth.frames_per_shape: 0"},
      {"MouthRatioOne", [](auto& r) { r.mutable_mouth()->set_mid_ratio(1.0); }, kInvalid,
       "mouth.mid_ratio: 1"},
      {"MouthRatioNaN", [](auto& r) { r.mutable_mouth()->set_mid_ratio(kNaN); }, kInvalid,
       "mouth.mid_ratio: nan"},
      {"MouthMinAboveMax",
       [](auto& r) {
         r.mutable_mouth()->set_min(1.0);
         r.mutable_mouth()->set_max(0.5);
       },
       kInvalid, "mouth.min"},
      {"SpeechReversed",
       [](auto& r) { AddInterval(r.mutable_mouth()->mutable_speech(), 30, 20); }, kInvalid,
       "mouth.speech[0]"},
      {"SpeechOutsideClip",
       [](auto& r) { AddInterval(r.mutable_mouth()->mutable_speech(), 50, 70); }, kInvalid,
       "mouth.speech[0]"},
      {"SpeechOverlapping",
       [](auto& r) {
         AddInterval(r.mutable_mouth()->mutable_speech(), 10, 30);
         AddInterval(r.mutable_mouth()->mutable_speech(), 25, 40);
       },
       kInvalid, "mouth.speech[1]"},
      {"EyeRatioZero", [](auto& r) { r.mutable_eyes()->set_mid_ratio(0.0); }, kInvalid,
       "eyes.mid_ratio: 0"},
      {"EyeThresholdHalf", [](auto& r) { r.mutable_eyes()->set_threshold(0.5); }, kInvalid,
       "eyes.threshold: 0.5"},
      {"EyeMinNaN", [](auto& r) { r.mutable_eyes()->set_min(kNaN); }, kInvalid,
       "eyes.min: nan"},
      {"AutoBlinkMeanZero",
       [](auto& r) {
         r.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
         r.mutable_eyes()->mutable_auto_blink()->set_mean_interval_s(0.0);
       },
       kInvalid, "eyes.auto_blink.mean_interval_s: 0"},
      {"AutoBlinkSpreadTooWide",
       [](auto& r) {
         r.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
         r.mutable_eyes()->mutable_auto_blink()->set_mean_interval_s(2.0);
         r.mutable_eyes()->mutable_auto_blink()->set_spread_s(3.0);
       },
       kInvalid, "eyes.auto_blink.spread_s: 3"},
      {"AutoBlinkHoldFour",
       [](auto& r) {
         r.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
         r.mutable_eyes()->mutable_auto_blink()->set_hold(4);
       },
       kInvalid, "eyes.auto_blink.hold: 4"},
      {"AutoBlinkKeepReversed",
       [](auto& r) {
         r.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
         AddInterval(r.mutable_eyes()->mutable_auto_blink()->mutable_keep(), 9, 3);
       },
       kInvalid, "eyes.auto_blink.keep[0]"},
      {"KeysTooLargeToInterpolate",
       [](auto& r) {
         v1::Curve* mouth = r.mutable_curves()->mutable_curves(0);
         mouth->clear_samples();
         mouth->mutable_start()->set_value(-1.5e308);
         v1::CurveSegment* segment = mouth->add_segments();
         segment->set_type(v1::SEGMENT_LINEAR);
         segment->mutable_end()->set_frame(59);
         segment->mutable_end()->set_value(1.5e308);
       },
       C::OUT_OF_RANGE, "curves.curves[0]: evaluates to"},
      {"OverValueLimit",
       [](auto& r) {
         r.mutable_curves()->set_frame_count(20'000);
         r.mutable_curves()->mutable_curves(0)->mutable_samples()->Resize(20'000, 0.0);
       },
       C::RESOURCE_EXHAUSTED, "--max_values=50000"},
  };
}

class LipBlinkBadRequestTest
    : public koma::testing::BadRequestSuite<LipBlinkBadRequestTest, v1::LipBlinkRequest> {
 public:
  static server::ServerConfig SuiteConfig() { return InProcessServer::Config(1, 50'000); }
  static v1::LipBlinkRequest ValidRequest() { return koma::testing::MakeLipBlinkRequest(); }
};

KOMA_BAD_REQUEST_TABLE(LipBlinkBadRequestTest, LipBlinkBadRequestTableTest, BadRequests)

}  // namespace
}  // namespace koma::server
