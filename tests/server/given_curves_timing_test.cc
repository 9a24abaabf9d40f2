// A given RetimeCurves timing (docs/semantics.md, "A given timing") through an in-process
// channel to the real service: bad given timings refused naming the field and value; random
// given timings come back unchanged per counted frame (the identity), the curves showing the
// given drawings (exact_taus: a dense curve's sample at each given tau, by an evaluator of its
// own); a computed answer's timings given back give the same bytes but the `given` marks.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/split_mix64.h"
#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"
#include "tests/server/bad_request_table.h"
#include "tests/server/curves_request_builder.h"
#include "tests/server/in_process_server.h"

namespace koma::server {
namespace {

using ::koma::testing::AddRandomKeyframes;
using ::koma::testing::CallRpc;
using ::koma::testing::InProcessServer;
using BadRequest = ::koma::testing::BadRequest<v1::RetimeCurvesRequest>;

// `frames` frames at `fps`: keyframe curves "B0", "B1" (the default group) and "H0" (group
// "hair", named when `hair`), and the dense curve "D" (samples 0, 1, 4, 9, ...: f^2) in the
// default group.
v1::RetimeCurvesRequest Clip(SplitMix64& rng, int frames, double fps, bool hair) {
  v1::RetimeCurvesRequest r;
  v1::CurveSet* set = r.mutable_curves();
  set->set_fps(fps);
  set->set_frame_count(frames);
  for (const char* id : {"B0", "B1", "H0"}) {
    v1::Curve* curve = set->add_curves();
    curve->set_id(id);
    AddRandomKeyframes(rng, frames, 3, 9, 0, curve);
  }
  v1::Curve* dense = set->add_curves();
  dense->set_id("D");
  for (int f = 0; f < frames; ++f) dense->add_samples(static_cast<double>(f) * f);
  if (hair) {
    v1::CurveTimingGroup* group = r.add_timing_groups();
    group->set_name("hair");
    group->add_ids("H*");
  } else {
    r.set_default_timing_groups(false);
  }
  return r;
}

v1::GivenDrawingTiming* Give(v1::RetimeCurvesRequest& r, const std::string& group,
                             const std::vector<double>& taus) {
  v1::GivenDrawingTiming* given = r.add_given_timings();
  given->set_group(group);
  for (double t : taus) given->add_source_frame(t);
  return given;
}

// The valid request: 31 frames at 24 fps (no grid), groups "body" and "hair", "body" given.
std::vector<BadRequest> BadRequests() {
  using C = grpc::StatusCode;
  const C kInvalid = C::INVALID_ARGUMENT;
  const auto taus = [](int n, double v) { return std::vector<double>(static_cast<size_t>(n), v); };
  return {
      {"UnknownGroup", [&](auto& r) { Give(r, "hat", taus(31, 0)); }, kInvalid,
       "given_timings[1].group: no timing group named \"hat\" (the groups: body, hair, keep)"},
      {"KeepGroup", [&](auto& r) { Give(r, "keep", taus(31, 0)); }, kInvalid,
       "given_timings[1].group: \"keep\" is a GROUP_KEEP group: its curves have no timing"},
      {"GroupWithoutCurves",
       [&](auto& r) {
         r.mutable_timing_groups(0)->set_ids(0, "Nothing*");
         Give(r, "hair", taus(31, 0));
       },
       kInvalid, "given_timings[1].group: \"hair\" has no curves in this request"},
      {"GroupTwice", [&](auto& r) { Give(r, "", taus(31, 0)); }, kInvalid,
       "given_timings[1].group: \"body\" already has given_timings[0]"},
      {"TooShort", [&](auto& r) { r.mutable_given_timings(0)->mutable_source_frame()->RemoveLast(); },
       kInvalid,
       "given_timings[0].source_frame: 30 values, but the clip has 31 frames (one tau per frame)"},
      {"TooLong", [&](auto& r) { r.mutable_given_timings(0)->add_source_frame(3); }, kInvalid,
       "given_timings[0].source_frame: 32 values, but the clip has 31 frames"},
      {"NaN", [&](auto& r) { r.mutable_given_timings(0)->set_source_frame(4, std::nan("")); },
       kInvalid, "given_timings[0].source_frame[4]: nan must be finite and >= 0"},
      {"Negative", [&](auto& r) { r.mutable_given_timings(0)->set_source_frame(2, -0.5); },
       kInvalid, "given_timings[0].source_frame[2]: -0.5 must be finite and >= 0"},
      {"PastTheEnd", [&](auto& r) { r.mutable_given_timings(0)->set_source_frame(7, 30.25); },
       kInvalid, "given_timings[0].source_frame[7]: 30.25 is past the clip's last frame 30"},
      {"GridLength",
       [&](auto& r) {
         r.mutable_curves()->set_fps(30);  // 31 frames at 30 fps: 25 grid frames
       },
       kInvalid,
       "given_timings[0].source_frame: 31 values, but the clip has 25 grid frames (one tau per "
       "frame)"},
  };
}

class GivenCurvesBadRequestTest
    : public koma::testing::BadRequestSuite<GivenCurvesBadRequestTest, v1::RetimeCurvesRequest> {
 public:
  static server::ServerConfig SuiteConfig() { return InProcessServer::Config(1, 50'000); }
  static v1::RetimeCurvesRequest ValidRequest() {
    SplitMix64 rng(1);
    v1::RetimeCurvesRequest r = Clip(rng, 31, 24, /*hair=*/true);
    v1::CurveTimingGroup* keep = r.add_timing_groups();
    keep->set_name("keep");
    keep->add_ids("K*");
    keep->set_mode(v1::GROUP_KEEP);
    std::vector<double> taus;
    for (int f = 0; f < 31; ++f) taus.push_back(f / 2 * 2.0);  // on twos
    Give(r, "body", taus);
    return r;
  }
};

TEST_P(GivenCurvesBadRequestTest, AnswersCodeAndNamesTheField) { ExpectTheRowRefused(); }
INSTANTIATE_TEST_SUITE_P(Table, GivenCurvesBadRequestTest, ::testing::ValuesIn(BadRequests()),
                         ::koma::testing::RowName());
TEST(GivenCurvesBadRequestTableTest, TheValidRequestIsAccepted) {
  InProcessServer server(GivenCurvesBadRequestTest::SuiteConfig());
  ::koma::testing::ExpectAccepted(server.stub(), GivenCurvesBadRequestTest::ValidRequest());
}

// Integer source rates on the 24 fps grid (24: none): grid frame of source frame k is
// floor(24 k / fps), exactly.
constexpr int kRates[] = {24, 12, 30, 60};
int GridFrameOf(int k, int fps) { return static_cast<int>((int64_t{24} * k) / fps); }
int CountedFrames(int frames, int fps) {
  return fps == 24 ? frames : GridFrameOf(frames - 1, fps) + 1;
}

// The response's timing of `group` per counted frame: the tau of the drawing starting at or
// before each (drawing_start_grid on a grid, else drawing_start).
std::vector<double> CountedTaus(const v1::DrawingTiming& timing, bool grid, int counted) {
  const auto& starts = grid ? timing.drawing_start_grid() : timing.drawing_start();
  std::vector<double> taus;
  int d = 0;
  for (int g = 0; g < counted; ++g) {
    while (d + 1 < starts.size() && starts[d + 1] <= g) ++d;
    taus.push_back(timing.drawing_source_frame(d));
  }
  return taus;
}

// The index into timings of `group`'s timing.
int TimingOf(const v1::RetimeCurvesResponse& r, const std::string& group) {
  if (r.timing_groups_size() == 0) return 0;
  for (const auto& g : r.timing_groups()) {
    if (g.name() == group) return g.timing();
  }
  return -1;
}

// Random taus, one per counted frame: holds of 1-4 frames, half of them whole frames, some
// drawings repeated later or swapped backwards.
std::vector<double> RandomTaus(SplitMix64& rng, int counted, int frames) {
  std::vector<double> taus;
  while (static_cast<int>(taus.size()) < counted) {
    double tau = rng.OneIn(2) ? rng.Int(0, frames - 1) : rng.Unit() * (frames - 1);
    if (!taus.empty() && rng.OneIn(4)) tau = taus[static_cast<size_t>(rng.Int(0, taus.size() - 1))];
    if (!taus.empty() && tau == taus.back()) continue;  // a new drawing
    for (int k = rng.Int(1, 4); k > 0 && static_cast<int>(taus.size()) < counted; --k) {
      taus.push_back(tau);
    }
  }
  return taus;
}

class GivenCurvesTimingTest : public ::testing::Test {
 protected:
  InProcessServer server_{InProcessServer::Config(2, 1'000'000)};
};

TEST_F(GivenCurvesTimingTest, AGivenTimingComesBackUnchangedAndTheCurvesShowIt) {
  SplitMix64 rng(460);
  for (int round = 0; round < 80; ++round) {
    const int fps = kRates[rng.Int(0, 3)];
    const int frames = rng.Int(fps / 12 + 3, 80);
    const bool hair = rng.OneIn(2);
    v1::RetimeCurvesRequest r = Clip(rng, frames, fps, hair);
    if (rng.OneIn(2)) r.set_frames_per_drawing(rng.Int(1, 4));
    const int counted = CountedFrames(frames, fps);
    const std::vector<double> body = RandomTaus(rng, counted, frames);
    const bool exact = rng.OneIn(2);
    Give(r, rng.OneIn(2) ? "" : "body", body)->set_exact_taus(exact);
    std::vector<double> hair_taus;
    if (hair && rng.OneIn(2)) {
      hair_taus = RandomTaus(rng, counted, frames);
      Give(r, "hair", hair_taus);
    }
    SCOPED_TRACE(::testing::Message() << "round " << round << ": " << frames << " frames at "
                                      << fps << " fps, hair " << hair << ", exact " << exact);
    v1::RetimeCurvesResponse a;
    const grpc::Status status = CallRpc(server_.stub(), r, &a);
    ASSERT_TRUE(status.ok()) << status.error_message();
    const bool grid = fps != 24;
    const int body_timing = TimingOf(a, "body");
    ASSERT_GE(body_timing, 0);
    const v1::DrawingTiming& t = a.timings(body_timing);
    EXPECT_TRUE(t.given());
    EXPECT_EQ(CountedTaus(t, grid, counted), body);  // the identity
    if (!hair_taus.empty()) {
      const v1::DrawingTiming& h = a.timings(TimingOf(a, "hair"));
      EXPECT_TRUE(h.given());
      EXPECT_EQ(CountedTaus(h, grid, counted), hair_taus);
    } else if (hair) {
      EXPECT_FALSE(a.timings(TimingOf(a, "hair")).given());
    }
    // The dense curve D (f^2, in the default group) at output frame k: with exact taus, its
    // sample at the tau given for k's grid frame, where that tau is a whole frame.
    const v1::RetimedCurve& d = a.curves(3);
    ASSERT_EQ(d.id(), "D");
    EXPECT_EQ(d.timing(), body_timing);
    ASSERT_EQ(d.values_size(), frames);
    for (int k = 0; k < frames; ++k) {
      const double tau = body[static_cast<size_t>(grid ? GridFrameOf(k, fps) : k)];
      if (exact && tau == std::floor(tau)) EXPECT_EQ(d.values(k), tau * tau) << k;
    }
    if (exact) EXPECT_EQ(d.keys_size(), 0);
  }
}

TEST_F(GivenCurvesTimingTest, ExactTausShowEachDrawingAtItsTauWhateverTheOrder) {
  // A keyframe curve that is its own time (one linear segment 0 -> last frame; its first and
  // last keys are keys the rule would draw), drawings swapped and repeated backwards: with
  // exact_taus each output frame shows the curve at the tau given for its grid frame.
  SplitMix64 rng(4603);
  for (int round = 0; round < 30; ++round) {
    const int fps = kRates[rng.Int(0, 3)];
    const int frames = rng.Int(fps / 12 + 3, 80);
    v1::RetimeCurvesRequest r;
    r.set_default_timing_groups(false);
    v1::CurveSet* set = r.mutable_curves();
    set->set_fps(fps);
    set->set_frame_count(frames);
    v1::Curve* time = set->add_curves();
    time->set_id("T");
    ::koma::testing::SetPoint(0, 0, time->mutable_start());
    v1::CurveSegment* segment = time->add_segments();
    segment->set_type(v1::SEGMENT_LINEAR);
    ::koma::testing::SetPoint(frames - 1, frames - 1, segment->mutable_end());
    const int counted = CountedFrames(frames, fps);
    const std::vector<double> taus = RandomTaus(rng, counted, frames);
    Give(r, "body", taus)->set_exact_taus(true);
    SCOPED_TRACE(::testing::Message() << "round " << round << ": " << frames << " at " << fps);
    v1::RetimeCurvesResponse a;
    const grpc::Status status = CallRpc(server_.stub(), r, &a);
    ASSERT_TRUE(status.ok()) << status.error_message();
    for (int k = 0; k < frames; ++k) {
      const double tau = taus[static_cast<size_t>(fps == 24 ? k : GridFrameOf(k, fps))];
      EXPECT_NEAR(a.curves(0).values(k), tau, 1e-9 * frames) << k;
    }
  }
}

TEST_F(GivenCurvesTimingTest, AComputedTimingGivenBackGivesTheSameBytes) {
  SplitMix64 rng(4600);
  for (int round = 0; round < 40; ++round) {
    const int fps = kRates[rng.Int(0, 3)];
    const int frames = rng.Int(fps / 12 + 3, 90);
    const bool hair = rng.OneIn(2);
    v1::RetimeCurvesRequest r = Clip(rng, frames, fps, hair);
    if (rng.OneIn(2)) r.set_frames_per_drawing(rng.Int(1, 4));
    if (rng.OneIn(3)) r.set_tame(1.0 + rng.Unit());
    if (rng.OneIn(3)) r.set_merge_key_poses(false);
    SCOPED_TRACE(::testing::Message() << "round " << round << ": " << frames << " at " << fps);
    v1::RetimeCurvesResponse computed;
    ASSERT_TRUE(CallRpc(server_.stub(), r, &computed).ok());
    const int counted = CountedFrames(frames, fps);
    v1::RetimeCurvesRequest given_request = r;
    for (const char* group : {"body", "hair"}) {
      if (!hair && std::string(group) == "hair") continue;
      const v1::DrawingTiming& t = computed.timings(TimingOf(computed, group));
      Give(given_request, group, CountedTaus(t, fps != 24, counted));
    }
    v1::RetimeCurvesResponse given;
    const grpc::Status status = CallRpc(server_.stub(), given_request, &given);
    ASSERT_TRUE(status.ok()) << status.error_message();
    for (auto& t : *given.mutable_timings()) {
      EXPECT_TRUE(t.given());
      t.clear_given();
    }
    EXPECT_EQ(given.SerializeAsString(), computed.SerializeAsString());
  }
}

}  // namespace
}  // namespace koma::server
