// Bad film-grid input through the real service (in-process channel), for RetimeCurves and
// LipBlink: timing_fps not finite or over 1000, a source rate the grid cannot count, a clip
// shorter than two grid frames, a grid finer than the clip over --max_values, speech intervals
// that vanish on the grid, segment overrides whose segment merged away on the grid. Each gets
// its code and a message naming the field and the value; none crashes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "koma/v1/retime.grpc.pb.h"
#include "tests/server/bad_request_table.h"
#include "tests/server/curves_request_builder.h"
#include "tests/server/in_process_server.h"
#include "tests/server/lip_blink_request_builder.h"

namespace koma::server {
namespace {

using ::koma::testing::CallRpc;
using ::koma::testing::ExpectRefused;
using ::koma::testing::InProcessServer;
using ::koma::testing::RowName;
using ::koma::testing::SharedServerTest;
using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int64_t kMaxValues = 50'000;

// One bad request, applied to both RPCs' sample requests (30 fps, 31 and 60 frames).
struct BadGrid {
  std::string name;
  std::function<void(v1::CurveSet&)> set;  // on the request's curves
  std::optional<double> timing_fps;        // unset: the default grid
  grpc::StatusCode code;
  std::vector<std::string> message;  // substrings
  friend void PrintTo(const BadGrid& bad, std::ostream* os) { *os << bad.name; }
};

void Keep(v1::CurveSet&) {}

// n frames at `fps` of every curve: dense samples cut or repeated to length n.
std::function<void(v1::CurveSet&)> Frames(int n, double fps) {
  return [n, fps](v1::CurveSet& set) {
    set.set_fps(fps);
    set.set_frame_count(n);
    for (v1::Curve& c : *set.mutable_curves()) {
      if (c.samples_size() == 0) {
        // Keyframes may lie past the clip: only the times change meaning.
        continue;
      }
      std::vector<double> v(c.samples().begin(), c.samples().end());
      c.clear_samples();
      for (int f = 0; f < n; ++f) c.add_samples(v[static_cast<size_t>(f) % v.size()]);
    }
  };
}

std::vector<BadGrid> BadRequests() {
  using C = grpc::StatusCode;
  return {
      {"TimingFpsNaN", Keep, kNaN, C::INVALID_ARGUMENT, {"timing_fps: nan", "finite"}},
      {"TimingFpsInf", Keep, kInf, C::INVALID_ARGUMENT, {"timing_fps: inf"}},
      {"TimingFpsMinusInf", Keep, -kInf, C::INVALID_ARGUMENT, {"timing_fps: -inf"}},
      {"TimingFps1001", Keep, 1001.0, C::INVALID_ARGUMENT, {"timing_fps: 1001", "<= 1000"}},
      {"FpsZero", [](v1::CurveSet& s) { s.set_fps(0.0); }, std::nullopt, C::INVALID_ARGUMENT,
       {"curves.fps: 0"}},
      {"FpsNaN", [](v1::CurveSet& s) { s.set_fps(kNaN); }, std::nullopt, C::INVALID_ARGUMENT,
       {"curves.fps: nan"}},
      {"FpsNaNNoGrid", [](v1::CurveSet& s) { s.set_fps(kNaN); }, 0.0, C::INVALID_ARGUMENT,
       {"curves.fps: nan"}},
      {"FpsInf", [](v1::CurveSet& s) { s.set_fps(kInf); }, std::nullopt, C::INVALID_ARGUMENT,
       {"curves.fps: inf"}},
      // A valid rate, but one frame every 10^4 s: no grid can count it.
      {"FpsTooSlowForAGrid", [](v1::CurveSet& s) { s.set_fps(1e-4); }, std::nullopt,
       C::INVALID_ARGUMENT, {"curves.fps", "0.0001"}},
      {"TwoFramesAt30SpanOneGridFrame", Frames(2, 30.0), std::nullopt, C::OUT_OF_RANGE,
       {"curves.frame_count: 2", "30 fps", "timing_fps"}},
      {"FourFramesAt120", Frames(4, 120.0), 24.0, C::OUT_OF_RANGE, {"curves.frame_count: 4"}},
      // 100 frames at 1 fps on a 1000 fps grid: 99,001 grid frames per curve.
      {"UpsamplingOverMaxValues", Frames(100, 1.0), 1000.0, C::RESOURCE_EXHAUSTED,
       {"99001 frames", "--max_values=50000"}},
  };
}

class GridBadRequestTest : public SharedServerTest<GridBadRequestTest, BadGrid> {
 public:
  static server::ServerConfig SuiteConfig() { return InProcessServer::Config(1, kMaxValues); }
};

TEST_P(GridBadRequestTest, RetimeCurvesAnswersCodeAndNamesTheFieldAndValue) {
  const BadGrid& bad = GetParam();
  v1::RetimeCurvesRequest request = koma::testing::MakeCurvesRequest();
  bad.set(*request.mutable_curves());
  if (bad.timing_fps) request.set_timing_fps(*bad.timing_fps);
  ExpectRefused(stub(), request, bad.code, bad.message, "RetimeCurves");
}

TEST_P(GridBadRequestTest, LipBlinkAnswersCodeAndNamesTheFieldAndValue) {
  const BadGrid& bad = GetParam();
  v1::LipBlinkRequest request = koma::testing::MakeLipBlinkRequest();
  bad.set(*request.mutable_curves());
  if (bad.timing_fps) request.set_timing_fps(*bad.timing_fps);
  ExpectRefused(stub(), request, bad.code, bad.message, "LipBlink");
}

INSTANTIATE_TEST_SUITE_P(Table, GridBadRequestTest, ::testing::ValuesIn(BadRequests()),
                         RowName());

// The same clips are fine where the grid is not in the way: counted in source frames, or a
// grid finer than the clip within the limit.
TEST(GridBadRequestTableTest, TheSameClipsAnswerWithoutTheGridOrWithinTheLimit) {
  InProcessServer server(InProcessServer::Config(1, kMaxValues));
  struct Case {
    std::function<void(v1::CurveSet&)> set;
    double timing_fps;
    int grid_frames;  // expected in key_grid_frames.back() + 1; 0: no grid
  };
  const Case cases[] = {{Frames(2, 30.0), 0.0, 0},  {Frames(4, 120.0), 0.0, 0},
                        {[](v1::CurveSet& s) { s.set_fps(1e-4); }, 0.0, 0},
                        {Frames(100, 1.0), 100.0, 9901}, {Frames(3, 30.0), 24.0, 2}};
  for (size_t i = 0; i < std::size(cases); ++i) {
    v1::RetimeCurvesRequest curves = koma::testing::MakeCurvesRequest();
    cases[i].set(*curves.mutable_curves());
    curves.set_timing_fps(cases[i].timing_fps);
    v1::RetimeCurvesResponse response;
    const grpc::Status status = CallRpc(server.stub(), curves, &response);
    ASSERT_TRUE(status.ok()) << "case " << i << ": " << status.error_message();
    if (cases[i].grid_frames == 0) {
      EXPECT_EQ(response.key_grid_frames_size(), 0) << i;
    } else {
      ASSERT_GT(response.key_grid_frames_size(), 0) << i;
      EXPECT_EQ(response.key_grid_frames(response.key_grid_frames_size() - 1) + 1,
                cases[i].grid_frames)
          << i;
      EXPECT_EQ(response.timings(0).drawing_of_frame_size(), curves.curves().frame_count()) << i;
    }
    v1::LipBlinkRequest lip = koma::testing::MakeLipBlinkRequest();
    cases[i].set(*lip.mutable_curves());
    lip.set_timing_fps(cases[i].timing_fps);
    v1::LipBlinkResponse lip_response;
    const grpc::Status lip_status = CallRpc(server.stub(), lip, &lip_response);
    ASSERT_TRUE(lip_status.ok()) << "case " << i << ": " << lip_status.error_message();
    EXPECT_EQ(lip_response.curves(0).values_size(), lip.curves().frame_count()) << i;
  }
}

// Key poses 0 .. 30 of the 31-frame 30 fps sample: on the grid (25 frames) several merge, so
// segment 29 of the source's 30 no longer exists; segment 0 still does.
TEST(GridBadRequestTableTest, SegmentOverrideOfAMergedSegmentIsInvalid) {
  InProcessServer server;
  v1::RetimeCurvesRequest request = koma::testing::MakeCurvesRequest();
  for (int f = 0; f <= 30; ++f) request.add_key_frames(f);
  request.add_segment_overrides()->set_segment(29);
  v1::RetimeCurvesResponse response;
  grpc::Status status = CallRpc(server.stub(), request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
  EXPECT_THAT(status.error_message(),
              AllOf(HasSubstr("segment_overrides[0].segment: 29 is outside [0, 24)"),
                    HasSubstr("25 key poses")));
  // Counted in source frames the same override is valid; on the grid segment 23 is the last.
  request.set_timing_fps(0.0);
  EXPECT_TRUE(CallRpc(server.stub(), request, &response).ok());
  request.clear_timing_fps();
  request.mutable_segment_overrides(0)->set_segment(23);
  status = CallRpc(server.stub(), request, &response);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(response.key_grid_frames_size(), 25);
  EXPECT_EQ(response.key_frames_size(), 25);
}

// Speech intervals of a frame or two at 120 fps snap to empty grid intervals: the call
// answers, with the intervals that are left.
TEST(GridBadRequestTableTest, SpeechThatVanishesOnTheGridDoesNotCrash) {
  InProcessServer server;
  v1::LipBlinkRequest request = koma::testing::MakeLipBlinkRequest();
  Frames(240, 120.0)(*request.mutable_curves());
  // The mouth talks all along (at the grid's times too).
  v1::Curve& mouth = *request.mutable_curves()->mutable_curves(0);
  ASSERT_EQ(mouth.id(), "ParamMouthOpenY");
  for (int f = 0; f < 240; ++f) mouth.set_samples(f, 0.5 + 0.5 * std::sin(f * 0.37));
  for (int begin : {11, 60, 130}) {  // [11, 13) -> grid [2, 3); [60, 61) -> [12, 12): gone
    v1::FrameInterval* speech = request.mutable_mouth()->add_speech();
    speech->set_begin(begin);
    speech->set_end(begin + (begin == 11 ? 2 : 1));
  }
  v1::LipBlinkResponse response;
  grpc::Status status = CallRpc(server.stub(), request, &response);
  ASSERT_TRUE(status.ok()) << status.error_message();
  ASSERT_EQ(response.mouths_size(), 1);
  ASSERT_EQ(response.mouths(0).speech_size(), 1);
  EXPECT_EQ(response.mouths(0).speech(0).begin(), 2);
  EXPECT_EQ(response.mouths(0).speech(0).end(), 3);
  EXPECT_GT(response.mouths(0).open_level(), 0.9);

  // Every interval gone: still an answer, with no speech (the intervals were given, so none is
  // detected in their place) and the mouth as it came in.
  request.mutable_mouth()->mutable_speech(0)->set_end(12);  // [11, 12) -> [2, 2)
  status = CallRpc(server.stub(), request, &response);
  ASSERT_TRUE(status.ok()) << status.error_message();
  ASSERT_EQ(response.mouths_size(), 1);
  EXPECT_EQ(response.mouths(0).speech_size(), 0);
  EXPECT_EQ(response.mouths(0).holds_size(), 0);
  ASSERT_EQ(response.curves(0).values_size(), 240);
  for (int f = 0; f < 240; ++f) ASSERT_EQ(response.curves(0).values(f), mouth.samples(f)) << f;
}

}  // namespace
}  // namespace koma::server
