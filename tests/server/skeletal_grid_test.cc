// RetimeSkeletal on the film grid (docs/semantics.md, "The film grid") through an in-process
// channel to the real service: bad timing_fps, source rates and grid-sized options get their code
// and a message naming the field; a 120 fps clip is timed on 24 fps grid frames and written back at
// 120 fps or, with TIMING_RATE, at 24; 24 fps input gives the bytes it gave without a grid.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"
#include "tests/server/bad_request_table.h"
#include "tests/server/in_process_server.h"
#include "tests/server/request_builder.h"

namespace koma::server {
namespace {

using ::koma::testing::InProcessServer;
using ::koma::testing::MakeSkeletalRequest;
using ::koma::testing::RawUnaryCall;
using ::koma::testing::SetTestDeadline;
using ::koma::testing::SharedServerTest;
using ::testing::HasSubstr;
using Mutation = std::function<void(v1::RetimeSkeletalRequest&)>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr char kSkeletalMethod[] = "/koma.v1.Retime/RetimeSkeletal";

// MakeSkeletalRequest's swing, `frames` frames at `fps`.
v1::RetimeSkeletalRequest MakeRequestAt(double fps, int frames) {
  v1::RetimeSkeletalRequest request = MakeSkeletalRequest(frames);
  request.mutable_motion()->set_frame_time(1.0 / fps);
  return request;
}

struct BadGridRequest {
  std::string name;
  int frames;  // of the base request, at 120 fps
  Mutation mutate;
  grpc::StatusCode code;
  std::string message;

  friend void PrintTo(const BadGridRequest& bad, std::ostream* os) { *os << bad.name; }
};

std::vector<BadGridRequest> BadGridRequests() {
  using C = grpc::StatusCode;
  const C kInvalid = C::INVALID_ARGUMENT;
  const auto frame_time = [](double s) {
    return [s](v1::RetimeSkeletalRequest& r) { r.mutable_motion()->set_frame_time(s); };
  };
  return {
      {"TimingFpsNaN", 30, [](auto& r) { r.set_timing_fps(kNaN); }, kInvalid,
       "timing_fps: nan must be finite and <= 1000 frames per second"},
      {"TimingFpsInf", 30, [](auto& r) { r.set_timing_fps(kInf); }, kInvalid,
       "timing_fps: inf must be finite"},
      {"TimingFpsMinusInf", 30, [](auto& r) { r.set_timing_fps(-kInf); }, kInvalid,
       "timing_fps: -inf must be finite"},
      {"TimingFps1001", 30, [](auto& r) { r.set_timing_fps(1001); }, kInvalid,
       "timing_fps: 1001 must be finite and <= 1000"},
      {"TimingFpsHuge", 30, [](auto& r) { r.set_timing_fps(1e300); }, kInvalid,
       "timing_fps: 1e+300 must be finite"},
      {"TimingFpsTiny", 30, [](auto& r) { r.set_timing_fps(1e-300); }, C::OUT_OF_RANGE,
       "span less than 2 frames of the 1e-300 fps film grid (timing_fps)"},
      {"FrameTimeZero", 30, frame_time(0.0), kInvalid,
       "motion.frame_time: 0 s must be finite and > 0"},
      {"FrameTimeNaN", 30, frame_time(kNaN), kInvalid, "motion.frame_time: nan"},
      {"FrameTimeNaNTimingFpsZero", 30,
       [](auto& r) {
         r.mutable_motion()->set_frame_time(kNaN);
         r.set_timing_fps(0);
       },
       kInvalid, "motion.frame_time: nan"},
      {"SourceRateTooLow", 30, frame_time(2000.0), kInvalid,
       "motion.frame_time: 2000 s: a rate of 0.0005 frames per second is outside 0.001 .. 1e+06"},
      {"SourceRateTooHigh", 30, frame_time(1e-9), kInvalid,
       "motion.frame_time: 1e-09 s: a rate of 1e+09 frames per second is outside"},
      {"ShorterThanTwoGridFrames", 5, [](auto&) {}, C::OUT_OF_RANGE,
       "motion: 5 frames at 120 fps (4 x 0.00833333 s) span less than 2 frames of the 24 fps "
       "film grid (timing_fps)"},
      {"ShorterThanTwoGridFramesAt12", 5, [](auto& r) { r.set_timing_fps(12); }, C::OUT_OF_RANGE,
       "span less than 2 frames of the 12 fps film grid"},
      {"OutputRate7", 30, [](auto& r) { r.set_output_rate(static_cast<v1::OutputRate>(7)); },
       kInvalid, "output_rate: 7 is not an OutputRate (1 SOURCE_RATE, 2 TIMING_RATE)"},
      // 30 frames at 120 fps are 6 grid frames: 5 omissions fit the source, not the grid.
      {"OmissionsOverTheGrid", 30, [](auto& r) { r.set_omissions(5); }, C::OUT_OF_RANGE,
       "omissions: 5"},
      {"OmissionsOverTheGridSaySo", 30, [](auto& r) { r.set_omissions(5); }, C::OUT_OF_RANGE,
       "(counted on the 24 fps film grid, where the clip has 6 frames; timing_fps: 0 counts in "
       "source frames)"},
      {"NegativeHoldsOnTheGrid", 30, [](auto& r) { r.set_holds(-1); }, kInvalid, "holds: -1"},
      {"MaxHoldZeroOnTheGrid", 30, [](auto& r) { r.set_max_hold(0); }, kInvalid, "max_hold: 0"},
      // 10 frames 100 s apart: 21601 grid frames x 3 joints x 3 = 194409 values to compare.
      {"GridOverValueLimit", 10, frame_time(100.0), C::RESOURCE_EXHAUSTED,
       "motion: 21601 frames on the 24 fps grid (timing_fps) x 9 values per frame = 194409 "
       "exceeds the server limit --max_values=50000"},
  };
}

class BadGridRequestTest : public SharedServerTest<BadGridRequestTest, BadGridRequest> {
 public:
  static server::ServerConfig SuiteConfig() { return InProcessServer::Config(2, 50'000); }
};

TEST_P(BadGridRequestTest, AnswersCodeAndNamesTheField) {
  const BadGridRequest& bad = GetParam();
  v1::RetimeSkeletalRequest request = MakeRequestAt(120.0, bad.frames);
  bad.mutate(request);
  koma::testing::ExpectRefused(stub(), request, bad.code, {bad.message});
}

INSTANTIATE_TEST_SUITE_P(Table, BadGridRequestTest, ::testing::ValuesIn(BadGridRequests()),
                         koma::testing::RowName());

TEST(SkeletalGridLimitTest, VastUpsamplingIsRefusedByTheValueLimitNotWrapped) {
  // 100000 frames 1000 s apart are 2.4e9 grid frames, more than an int holds: the count
  // saturates and the limit refuses it (it wrapped to a negative count before).
  ServerConfig config = InProcessServer::Config(1, 2'000'000);
  InProcessServer server(config);
  v1::RetimeSkeletalRequest request = MakeSkeletalRequest(2);
  v1::SkeletalMotion* motion = request.mutable_motion();
  motion->clear_channels();
  motion->set_frame_time(1000.0);
  motion->set_frame_count(100000);
  auto* values = motion->mutable_positions()->mutable_values();
  values->Reserve(900000);
  for (int i = 0; i < 900000; ++i) values->Add(0.001 * (i % 977));
  grpc::ClientContext context;
  SetTestDeadline(context, 60);
  v1::RetimeSkeletalResponse response;
  const grpc::Status status = server.stub().RetimeSkeletal(&context, request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  EXPECT_THAT(status.error_message(),
              HasSubstr("motion: 2147483647 frames on the 24 fps grid (timing_fps)"));
}

// The answer's bytes as the server sent them; they must also be what protobuf writes.
std::string Answer(InProcessServer& server, const v1::RetimeSkeletalRequest& request,
                   v1::RetimeSkeletalResponse* response) {
  std::string bytes;
  const grpc::Status status =
      RawUnaryCall(server, kSkeletalMethod, request.SerializeAsString(), &bytes);
  EXPECT_TRUE(status.ok()) << status.error_message();
  EXPECT_TRUE(response->ParseFromString(bytes));
  EXPECT_EQ(response->SerializeAsString(), bytes) << "not protobuf's bytes";
  return bytes;
}

TEST(SkeletalGridTest, OneHundredTwentyFpsIsTimedOnTheGridAndKeepsItsRate) {
  InProcessServer server(InProcessServer::Config(2, 20'000'000));
  v1::RetimeSkeletalRequest request = MakeRequestAt(120.0, 121);  // one second
  request.set_max_hold(3);  // a count named: the paper's defaults for the others
  v1::RetimeSkeletalResponse response;
  Answer(server, request, &response);

  EXPECT_EQ(response.timing_fps(), 24.0);
  ASSERT_EQ(response.grid_source_frames_size(), 25);  // grid frames 0 .. 24
  for (int g = 0; g < 25; ++g) EXPECT_EQ(response.grid_source_frames(g), 5 * g) << g;
  // The paper's defaults and counts on the grid's 25 frames.
  EXPECT_EQ(response.omissions_requested(), 4);
  EXPECT_EQ(response.holds_requested(), 8);  // 25 / 3
  EXPECT_EQ(response.max_hold(), 3);
  EXPECT_EQ(response.input_ssd_size(), 25);
  EXPECT_GT(response.holds_applied(), 0);
  // Written back at 120 fps: source frame k shows the drawing of grid frame k / 5.
  ASSERT_EQ(response.source_frames_size(), 121);
  ASSERT_EQ(response.kinds_size(), 121);
  ASSERT_EQ(response.grid_frames_size(), 121);
  int runs = 0;
  for (int k = 0; k < 121; ++k) {
    EXPECT_EQ(response.grid_frames(k), k / 5) << k;
    EXPECT_EQ(response.source_frames(k) % 5, 0) << "frame " << k << " shows an unsampled frame";
    if (k > 0 && response.source_frames(k) != response.source_frames(k - 1)) {
      EXPECT_EQ(k % 5, 0) << "a drawing changes inside a grid frame at " << k;
      ++runs;
    }
  }
  EXPECT_LT(runs + 1, 25) << "holds and omissions leave fewer drawings than grid frames";
  for (int32_t gone : response.deleted_frames()) EXPECT_EQ(gone % 5, 0) << gone;
  for (int32_t gone : response.hidden_frames()) EXPECT_EQ(gone % 5, 0) << gone;
  const v1::SkeletalMotion& out = response.motion();
  EXPECT_EQ(out.frame_time(), request.motion().frame_time());
  EXPECT_EQ(out.frame_count(), 121);
  const auto& in_values = request.motion().channels().values();
  ASSERT_EQ(out.channels().values_size(), 121 * 12);
  for (int t = 0; t < 121; ++t) {
    for (int c = 0; c < 12; ++c) {
      ASSERT_EQ(out.channels().values(t * 12 + c), in_values[response.source_frames(t) * 12 + c]);
    }
  }
}

TEST(SkeletalGridTest, TimingRateWritesOneFramePerGridFrame) {
  InProcessServer server(InProcessServer::Config(1, 20'000'000));
  v1::RetimeSkeletalRequest request = MakeRequestAt(120.0, 121);
  v1::RetimeSkeletalResponse at_source;
  Answer(server, request, &at_source);
  request.set_output_rate(v1::TIMING_RATE);
  v1::RetimeSkeletalResponse response;
  Answer(server, request, &response);

  EXPECT_EQ(response.motion().frame_time(), 1.0 / 24.0);
  EXPECT_EQ(response.motion().frame_count(), 25);
  ASSERT_EQ(response.source_frames_size(), 25);
  ASSERT_EQ(response.grid_frames_size(), 25);
  for (int t = 0; t < 25; ++t) {
    EXPECT_EQ(response.grid_frames(t), t);
    // The same drawings as at the source rate, one per grid frame.
    EXPECT_EQ(response.source_frames(t), at_source.source_frames(5 * t)) << t;
    EXPECT_EQ(response.kinds(t), at_source.kinds(5 * t)) << t;
  }
  EXPECT_EQ(response.motion().channels().values_size(), 25 * 12);
  // Without the motion too.
  request.set_return_motion(false);
  v1::RetimeSkeletalResponse bare;
  Answer(server, request, &bare);
  EXPECT_FALSE(bare.has_motion());
  EXPECT_EQ(bare.source_frames_size(), 25);
  EXPECT_EQ(bare.grid_frames_size(), 25);
}

TEST(SkeletalGridTest, TimingFpsZeroOrTheSourceRateCountsInSourceFrames) {
  InProcessServer server(InProcessServer::Config(1, 20'000'000));
  v1::RetimeSkeletalRequest request = MakeRequestAt(120.0, 121);
  request.set_timing_fps(0);
  request.set_max_hold(3);  // the paper's counts, of source frames here
  v1::RetimeSkeletalResponse response;
  const std::string no_grid = Answer(server, request, &response);
  EXPECT_EQ(response.timing_fps(), 0.0);
  EXPECT_EQ(response.grid_frames_size(), 0);
  EXPECT_EQ(response.grid_source_frames_size(), 0);
  EXPECT_EQ(response.holds_requested(), 40);  // 121 / 3
  EXPECT_EQ(response.input_ssd_size(), 121);
  for (double same : {-5.0, 120.0, 120.005}) {
    request.set_timing_fps(same);
    v1::RetimeSkeletalResponse again;
    EXPECT_EQ(Answer(server, request, &again), no_grid) << "timing_fps " << same;
  }
}

TEST(SkeletalGridTest, TwentyFourFpsGivesTheBytesItGaveWithoutAGrid) {
  InProcessServer server(InProcessServer::Config(2, 20'000'000));
  for (double frame_time : {1.0 / 24.0, 0.041667, 0.0416667, 0.04166667}) {
    SCOPED_TRACE(frame_time);
    v1::RetimeSkeletalRequest request = MakeSkeletalRequest(60);
    request.mutable_motion()->set_frame_time(frame_time);
    request.set_timing_fps(0);
    v1::RetimeSkeletalResponse response;
    const std::string no_grid = Answer(server, request, &response);
    ASSERT_FALSE(no_grid.empty());
    EXPECT_EQ(response.timing_fps(), 0.0);
    EXPECT_EQ(response.motion().frame_time(), frame_time);
    request.clear_timing_fps();  // the default, 24
    v1::RetimeSkeletalResponse unset;
    EXPECT_EQ(Answer(server, request, &unset), no_grid);
    request.set_timing_fps(24.0);
    v1::RetimeSkeletalResponse explicit_24;
    EXPECT_EQ(Answer(server, request, &explicit_24), no_grid);
    request.set_output_rate(v1::TIMING_RATE);  // no grid: nothing to write at its rate
    v1::RetimeSkeletalResponse timing_rate;
    EXPECT_EQ(Answer(server, request, &timing_rate), no_grid);
  }
}

TEST(SkeletalGridTest, SameRequestSameBytes) {
  const v1::RetimeSkeletalRequest request = MakeRequestAt(59.94, 300);
  std::string first;
  for (int threads : {1, 3}) {
    InProcessServer server(InProcessServer::Config(threads, 20'000'000));
    for (int i = 0; i < 3; ++i) {
      v1::RetimeSkeletalResponse response;
      const std::string bytes = Answer(server, request, &response);
      EXPECT_EQ(response.grid_source_frames_size(), 120);  // 299 / 59.94 s = 4.99 s
      if (first.empty()) first = bytes;
      EXPECT_EQ(bytes, first);
    }
  }
}

}  // namespace
}  // namespace koma::server
