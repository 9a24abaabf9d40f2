// 24 fps input is not on a grid (docs/semantics.md, "The film grid"): every RetimeCurves and
// LipBlink answer with timing_fps unset (the default 24), or 24, or the source's own rate, is the
// one with timing_fps 0, byte for byte, on random requests whose rate is 24, 24.0001 or 23.999
// (within the 1e-4 relative tolerance). Through the real service's wire path (in-process
// channel, raw bytes).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/split_mix64.h"
#include "koma/v1/retime.pb.h"
#include "tests/server/curves_request_builder.h"
#include "tests/server/in_process_server.h"

namespace koma::server {
namespace {

using ::koma::testing::InProcessServer;
using ::koma::testing::RawUnaryCall;

constexpr double kRates[] = {24.0, 24.0001, 23.999};
constexpr int kRequestsPerRate = 150;

v1::RetimeCurvesRequest RandomCurvesRequest(SplitMix64& rng, double fps) {
  v1::RetimeCurvesRequest request;
  v1::CurveSet* set = request.mutable_curves();
  const int frames = rng.OneIn(10) ? rng.Int(1000, 3000) : rng.Int(2, 300);
  set->set_fps(fps);
  set->set_frame_count(frames);
  set->set_beziers_restricted(rng.OneIn(2));
  const int curves = rng.Int(1, 6);
  for (int c = 0; c < curves; ++c) {
    v1::Curve* curve = set->add_curves();
    curve->set_id("P" + std::to_string(c));
    if (rng.OneIn(4)) {
      for (int f = 0; f < frames; ++f) curve->add_samples(rng.Unit() - 0.5);
    } else {
      ::koma::testing::AddRandomKeyframes(rng, frames, 1, 12, 4, curve);
    }
  }
  const int keys = ::koma::testing::AddRandomCurvesOptions(rng, 7, &request);
  for (int s = 0; s < std::max(1, keys - 1); ++s) {
    if (!rng.OneIn(3)) continue;
    v1::SegmentOverride* o = request.add_segment_overrides();
    o->set_segment(s);
    if (rng.OneIn(2)) o->set_frames_per_drawing(rng.Int(1, 4));
    if (rng.OneIn(2)) o->set_tame(1.0 + rng.Unit());
  }
  return request;
}

v1::LipBlinkRequest RandomLipBlinkRequest(SplitMix64& rng, double fps) {
  v1::LipBlinkRequest request;
  v1::CurveSet* set = request.mutable_curves();
  const int frames = rng.Int(2, 400);
  set->set_fps(fps);
  set->set_frame_count(frames);
  v1::Curve* mouth = set->add_curves();
  mouth->set_id("ParamMouthOpenY");
  bool talking = false;
  int left = 0;
  for (int f = 0; f < frames; ++f) {
    if (left-- <= 0) {
      talking = !talking;
      left = rng.Int(1, 30);
    }
    mouth->add_samples(talking ? rng.Unit() : 0.0);
  }
  for (const char* id : {"ParamEyeLOpen", "ParamEyeROpen"}) {
    v1::Curve* eye = set->add_curves();
    eye->set_id(id);
    int shut = 0;
    for (int f = 0; f < frames; ++f) {
      if (shut == 0 && rng.OneIn(40)) shut = rng.Int(2, 8);
      eye->add_samples(shut > 0 ? (shut-- > 2 ? 0.0 : 0.5) : 1.0);
    }
  }
  if (rng.OneIn(2)) request.mutable_mouth()->set_frames_per_shape(rng.Int(1, 4));
  if (rng.OneIn(2)) request.mutable_mouth()->set_mode(v1::MOUTH_FOLLOW);
  if (rng.OneIn(3)) {
    v1::FrameInterval* speech = request.mutable_mouth()->add_speech();
    speech->set_begin(rng.Int(0, frames - 1));
    speech->set_end(rng.Int(speech->begin() + 1, frames));
  }
  if (rng.OneIn(3)) request.mutable_eyes()->set_linked(false);
  if (rng.OneIn(3)) {
    request.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
    request.mutable_eyes()->mutable_auto_blink()->set_mean_interval_s(0.5 + rng.Unit());
  }
  if (rng.OneIn(2)) request.set_seed(rng.Next());
  return request;
}

// The raw answer bytes to `request` at each timing_fps in `grids` (nullopt: unset) equal the
// bytes at timing_fps 0.
template <typename Request>
void ExpectSameBytes(InProcessServer& server, const std::string& method, Request request,
                     const std::string& context) {
  request.set_timing_fps(0.0);
  std::string want;
  const grpc::Status want_status = RawUnaryCall(server, method, request.SerializeAsString(), &want);
  ASSERT_TRUE(want_status.ok()) << context << ": " << want_status.error_message();
  ASSERT_FALSE(want.empty());
  const double fps = request.curves().fps();
  for (const std::optional<double> grid : {std::optional<double>(), std::optional<double>(24.0),
                                           std::optional<double>(fps)}) {
    if (grid) {
      request.set_timing_fps(*grid);
    } else {
      request.clear_timing_fps();
    }
    std::string got;
    const grpc::Status status = RawUnaryCall(server, method, request.SerializeAsString(), &got);
    ASSERT_TRUE(status.ok()) << context << ": " << status.error_message();
    ASSERT_EQ(got, want) << context << ", timing_fps " << (grid ? std::to_string(*grid) : "unset");
  }
}

TEST(GridIdentityTest, CurvesAt24FpsAnswerTheBytesOfNoGrid) {
  InProcessServer server;
  for (double fps : kRates) {
    SplitMix64 rng(static_cast<uint64_t>(fps * 1e4));
    for (int i = 0; i < kRequestsPerRate; ++i) {
      ExpectSameBytes(server, "/koma.v1.Retime/RetimeCurves", RandomCurvesRequest(rng, fps),
                      "curves request " + std::to_string(i) + " at " + std::to_string(fps));
      if (HasFatalFailure()) return;
    }
  }
}

TEST(GridIdentityTest, LipBlinkAt24FpsAnswersTheBytesOfNoGrid) {
  InProcessServer server;
  for (double fps : kRates) {
    SplitMix64 rng(static_cast<uint64_t>(fps * 1e4) + 1);
    for (int i = 0; i < kRequestsPerRate; ++i) {
      ExpectSameBytes(server, "/koma.v1.Retime/LipBlink", RandomLipBlinkRequest(rng, fps),
                      "lipblink request " + std::to_string(i) + " at " + std::to_string(fps));
      if (HasFatalFailure()) return;
    }
  }
}

// At any rate, timing_fps <= 0 or within 1e-4 of the curves' own rate counts in source
// frames: the bytes of timing_fps 0.
TEST(GridIdentityTest, NegativeOrOwnRateTimingFpsAnswersTheBytesOfNoGrid) {
  InProcessServer server;
  SplitMix64 rng(31);
  for (const double fps : {30.0, 60.0, 12.0, 29.97}) {
    for (int i = 0; i < 20; ++i) {
      v1::RetimeCurvesRequest curves = RandomCurvesRequest(rng, fps);
      v1::LipBlinkRequest lip = RandomLipBlinkRequest(rng, fps);
      curves.set_timing_fps(0.0);
      lip.set_timing_fps(0.0);
      std::string want_curves, want_lip;
      ASSERT_TRUE(RawUnaryCall(server, "/koma.v1.Retime/RetimeCurves", curves.SerializeAsString(),
                               &want_curves)
                      .ok());
      ASSERT_TRUE(
          RawUnaryCall(server, "/koma.v1.Retime/LipBlink", lip.SerializeAsString(), &want_lip)
              .ok());
      for (const double timing : {-1.0, -1e300, -0.0, fps, fps * (1 + 0.9e-4)}) {
        curves.set_timing_fps(timing);
        lip.set_timing_fps(timing);
        std::string got_curves, got_lip;
        ASSERT_TRUE(RawUnaryCall(server, "/koma.v1.Retime/RetimeCurves",
                                 curves.SerializeAsString(), &got_curves)
                        .ok());
        ASSERT_TRUE(
            RawUnaryCall(server, "/koma.v1.Retime/LipBlink", lip.SerializeAsString(), &got_lip)
                .ok());
        ASSERT_EQ(got_curves, want_curves) << fps << " fps, timing_fps " << timing << ", " << i;
        ASSERT_EQ(got_lip, want_lip) << fps << " fps, timing_fps " << timing << ", " << i;
      }
    }
  }
}

// Just outside the tolerance (24 * (1 +- 2e-4)) the grid is used: the answers differ from
// timing_fps 0 (they carry timing_fps 24), so the comparison above can tell the two apart.
TEST(GridIdentityTest, RatesJustOutsideTheToleranceUseTheGrid) {
  InProcessServer server;
  SplitMix64 rng(5);
  for (double fps : {24.0 * (1 + 2e-4), 24.0 * (1 - 2e-4)}) {
    v1::RetimeCurvesRequest request = RandomCurvesRequest(rng, fps);
    request.mutable_curves()->set_frame_count(200);
    request.clear_key_frames();
    request.clear_segment_overrides();
    for (v1::Curve& c : *request.mutable_curves()->mutable_curves()) {
      c.Clear();
      c.set_id("P");
      for (int f = 0; f < 200; ++f) c.add_samples(f);
      break;
    }
    while (request.curves().curves_size() > 1) request.mutable_curves()->mutable_curves()->RemoveLast();
    request.clear_curve_overrides();
    std::string grid, none;
    ASSERT_TRUE(RawUnaryCall(server, "/koma.v1.Retime/RetimeCurves", request.SerializeAsString(),
                             &grid)
                    .ok());
    request.set_timing_fps(0.0);
    ASSERT_TRUE(RawUnaryCall(server, "/koma.v1.Retime/RetimeCurves", request.SerializeAsString(),
                             &none)
                    .ok());
    EXPECT_NE(grid, none) << fps;
    v1::RetimeCurvesResponse response;
    ASSERT_TRUE(response.ParseFromString(grid));
    EXPECT_EQ(response.timing_fps(), 24.0) << fps;
  }
}

}  // namespace
}  // namespace koma::server
