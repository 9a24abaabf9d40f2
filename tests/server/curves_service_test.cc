// RetimeCurves through an in-process channel: the answer's shape and consistency.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"
#include "tests/server/in_process_server.h"
#include "tests/server/curves_request_builder.h"

namespace koma::server {
namespace {

using ::testing::ElementsAre;

class CurvesServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ServerConfig config;
    config.address = "";
    config.worker_threads = 2;
    server_ = KomaServer::Start(config).value();
    stub_ = v1::Retime::NewStub(server_->InProcessChannel());
  }
  grpc::Status Call(const v1::RetimeCurvesRequest& request, v1::RetimeCurvesResponse* response) {
    return koma::testing::CallRpc(*stub_, request, response);
  }
  std::unique_ptr<KomaServer> server_;
  std::unique_ptr<v1::Retime::Stub> stub_;
};

// The paper's experiment (Miyamune et al. section 3.1): keys 0, 10, 25, ..., 100 on threes.
TEST_F(CurvesServiceTest, PaperKeysOnThreesHoldAtMostThreeAndStartDrawingsOnKeys) {
  v1::RetimeCurvesRequest request;
  v1::CurveSet* set = request.mutable_curves();
  set->set_fps(24.0);
  set->set_frame_count(101);
  v1::Curve* curve = set->add_curves();
  curve->set_id("ParamAngleX");
  for (int f = 0; f <= 100; ++f) curve->add_samples(0.5 * f);
  for (int k : {0, 10, 25, 35, 50, 60, 75, 85, 100}) request.add_key_frames(k);
  request.set_frames_per_drawing(3);
  v1::RetimeCurvesResponse response;
  ASSERT_TRUE(Call(request, &response).ok());

  EXPECT_THAT(response.key_frames(), ElementsAre(0, 10, 25, 35, 50, 60, 75, 85, 100));
  ASSERT_EQ(response.timings_size(), 1);
  const v1::DrawingTiming& timing = response.timings(0);
  ASSERT_EQ(timing.drawing_of_frame_size(), 101);
  for (int key : response.key_frames()) {
    EXPECT_TRUE(key == 0 ||
                timing.drawing_of_frame(key) != timing.drawing_of_frame(key - 1))
        << "a new drawing starts on key " << key;
    EXPECT_EQ(timing.source_frame(key), key);
  }
  // Segments of 10 frames hold 3,3,2,2; of 15 frames 3 x 5; the last frame alone.
  std::string histogram;
  for (const v1::HoldCount& count : response.curves(0).hold_histogram()) {
    histogram += std::to_string(count.length()) + "x" + std::to_string(count.drawings()) + " ";
    EXPECT_LE(count.length(), 3);
  }
  EXPECT_EQ(histogram, "1x1 2x8 3x28 ");  // 4 x (3,3,2,2) + 4 x (3,3,3,3,3) + the last frame
}

TEST_F(CurvesServiceTest, SteppedKeyframesMatchThePerFrameValues) {
  v1::RetimeCurvesRequest request = koma::testing::MakeCurvesRequest();
  request.set_frames_per_drawing(2);
  request.set_tame(1.5);
  request.set_tsume(2.0);
  v1::RetimeCurvesResponse response;
  ASSERT_TRUE(Call(request, &response).ok());
  ASSERT_EQ(response.curves_size(), 2);
  for (const v1::RetimedCurve& curve : response.curves()) {
    ASSERT_EQ(curve.values_size(), 31);
    const v1::Curve& stepped = curve.stepped();
    EXPECT_EQ(stepped.id(), curve.id());
    // Walk the stepped keyframes: frame f shows the value of the last point at or before f.
    int next = 0;  // index of the next segment end
    double shown = stepped.start().value();
    for (int f = 0; f < 31; ++f) {
      while (next < stepped.segments_size() && stepped.segments(next).end().frame() <= f) {
        EXPECT_EQ(stepped.segments(next).type(), v1::SEGMENT_STEPPED);
        shown = stepped.segments(next).end().value();
        ++next;
      }
      EXPECT_EQ(curve.values(f), shown) << curve.id() << " frame " << f;
    }
  }
}

TEST_F(CurvesServiceTest, PerCurveFramesPerDrawingGetTheirOwnTiming) {
  v1::RetimeCurvesRequest request = koma::testing::MakeCurvesRequest();
  request.set_frames_per_drawing(3);
  v1::CurveOverride* hair = request.add_curve_overrides();
  hair->set_curve_id("ParamArm");
  hair->set_frames_per_drawing(2);
  v1::RetimeCurvesResponse response;
  ASSERT_TRUE(Call(request, &response).ok());
  ASSERT_EQ(response.timings_size(), 2);
  EXPECT_EQ(response.timings(0).frames_per_drawing(), 3);
  EXPECT_EQ(response.curves(0).timing(), 0);
  const int arm_timing = response.curves(1).timing();
  EXPECT_EQ(response.timings(arm_timing).frames_per_drawing(), 2);
}

TEST_F(CurvesServiceTest, SameRequestSameBytes) {
  v1::RetimeCurvesRequest request = koma::testing::MakeCurvesRequest();
  request.set_tame(1.7);
  v1::RetimeCurvesResponse first;
  v1::RetimeCurvesResponse second;
  ASSERT_TRUE(Call(request, &first).ok());
  ASSERT_TRUE(Call(request, &second).ok());
  EXPECT_EQ(first.SerializeAsString(), second.SerializeAsString());
}

}  // namespace
}  // namespace koma::server
