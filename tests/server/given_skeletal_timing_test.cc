// A given RetimeSkeletal timing (docs/semantics.md, "A given timing") through an in-process
// channel to the real service: bad timings refused naming the field and value; random valid
// timings come back unchanged in the response (the identity), the motion showing exactly the
// given source frames; a computed answer's timing given back gives the same motion bytes; one
// timing on two rigs of one length gives one map.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/split_mix64.h"
#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"
#include "tests/server/bad_request_table.h"
#include "tests/server/in_process_server.h"
#include "tests/server/request_builder.h"
#include "tests/testing/gltf_builder.h"

namespace koma::server {
namespace {

using ::koma::testing::CallRpc;
using ::koma::testing::InProcessServer;
using ::koma::testing::MakeSkeletalRequest;
using BadRequest = ::koma::testing::BadRequest<v1::RetimeSkeletalRequest>;

void Give(v1::RetimeSkeletalRequest& r, const std::vector<int>& frames) {
  auto* given = r.mutable_given_timing()->mutable_source_frames();
  given->Clear();
  for (int f : frames) given->Add(f);
}

// The valid request: 10 frames at 24 fps (no grid), a given timing of 10 frames.
std::vector<BadRequest> BadRequests() {
  using C = grpc::StatusCode;
  const C kInvalid = C::INVALID_ARGUMENT;
  return {
      {"Empty", [](auto& r) { Give(r, {}); }, kInvalid,
       "given_timing.source_frames: empty; give the source frame of at least one frame"},
      {"PastTheLastFrame", [](auto& r) { Give(r, {0, 1, 2, 3, 4, 5, 6, 7, 812, 9}); }, kInvalid,
       "given_timing.source_frames[8]: 812 is past the clip's last frame 9"},
      {"Negative", [](auto& r) { Give(r, {0, -3}); }, kInvalid,
       "given_timing.source_frames[1]: -3 must be >= 0"},
      {"LongerThanTheClip", [](auto& r) { Give(r, std::vector<int>(11, 0)); }, kInvalid,
       "given_timing.source_frames: 11 frames is longer than the clip's 10 frames"},
      {"LongerThanTheGrid",
       [](auto& r) {
         // 10 frames at 120 fps span 9 / 5 s: grid frames 0 and 1 of the 24 fps grid.
         r.mutable_motion()->set_frame_time(1.0 / 120.0);
         Give(r, {0, 5, 9});
       },
       kInvalid, "given_timing.source_frames: 3 frames is longer than the clip's 2 grid frames"},
  };
}

class GivenSkeletalBadRequestTest
    : public koma::testing::BadRequestSuite<GivenSkeletalBadRequestTest,
                                            v1::RetimeSkeletalRequest> {
 public:
  static server::ServerConfig SuiteConfig() { return InProcessServer::Config(1, 50'000); }
  static v1::RetimeSkeletalRequest ValidRequest() {
    v1::RetimeSkeletalRequest r = MakeSkeletalRequest(10);
    Give(r, {0, 1, 1, 3, 3, 3, 9, 8, 2, 2});
    return r;
  }
};

// The table of KOMA_BAD_REQUEST_TABLE without its twenty-row floor: the rows are one field's.
TEST_P(GivenSkeletalBadRequestTest, AnswersCodeAndNamesTheField) { ExpectTheRowRefused(); }
INSTANTIATE_TEST_SUITE_P(Table, GivenSkeletalBadRequestTest, ::testing::ValuesIn(BadRequests()),
                         ::koma::testing::RowName());
TEST(GivenSkeletalBadRequestTableTest, TheValidRequestIsAccepted) {
  InProcessServer server(GivenSkeletalBadRequestTest::SuiteConfig());
  ::koma::testing::ExpectAccepted(server.stub(), GivenSkeletalBadRequestTest::ValidRequest());
}

// The source rates tried, each an integer fps on the 24 fps grid (24: no grid), so the grid
// frame of source frame k is exactly floor(24 k / fps): an independent reference.
constexpr int kRates[] = {24, 12, 30, 60, 120};

int GridFrameOf(int k, int fps) { return static_cast<int>((int64_t{24} * k) / fps); }
int CountedFrames(int frames, int fps) {
  return fps == 24 ? frames : GridFrameOf(frames - 1, fps) + 1;
}

// A random clip of `frames` frames at `fps`, a wider swing with noise so the computed timing
// is not trivial.
v1::RetimeSkeletalRequest RandomClip(SplitMix64& rng, int frames, int fps) {
  v1::RetimeSkeletalRequest r = MakeSkeletalRequest(frames);
  r.mutable_motion()->set_frame_time(1.0 / fps);
  auto* values = r.mutable_motion()->mutable_channels()->mutable_values();
  for (int i = 0; i < values->size(); ++i) values->Set(i, values->Get(i) + 20.0 * rng.Unit());
  return r;
}

class GivenSkeletalTimingTest : public ::testing::Test {
 protected:
  InProcessServer server_{InProcessServer::Config(2, 1'000'000)};
};

TEST_F(GivenSkeletalTimingTest, AGivenTimingComesBackUnchangedAndTheMotionShowsIt) {
  SplitMix64 rng(46);
  for (int round = 0; round < 120; ++round) {
    const int fps = kRates[rng.Int(0, 4)];
    const int frames = rng.Int(fps / 24 + 2, 90);  // at least 2 grid frames
    v1::RetimeSkeletalRequest r = RandomClip(rng, frames, fps);
    const bool timing_rate = rng.OneIn(2);
    if (timing_rate) r.set_output_rate(v1::TIMING_RATE);
    const int counted = CountedFrames(frames, fps);
    std::vector<int> given(static_cast<size_t>(rng.Int(1, counted)));
    for (int& s : given) s = rng.Int(0, frames - 1);
    for (size_t t = 1; t < given.size(); ++t) {  // holds too
      if (rng.OneIn(3)) given[t] = given[t - 1];
    }
    Give(r, given);
    SCOPED_TRACE(::testing::Message() << "round " << round << ": " << frames << " frames at "
                                      << fps << " fps, " << given.size() << " given");
    v1::RetimeSkeletalResponse a;
    const grpc::Status status = CallRpc(server_.stub(), r, &a);
    ASSERT_TRUE(status.ok()) << status.error_message();
    EXPECT_TRUE(a.timing_given());
    const bool grid = fps != 24;
    // The output frames and the counted frame each shows.
    std::vector<int> counted_of;
    if (!grid || timing_rate) {
      for (size_t t = 0; t < given.size(); ++t) counted_of.push_back(static_cast<int>(t));
    } else {
      for (int k = 0; k < frames && GridFrameOf(k, fps) < static_cast<int>(given.size()); ++k) {
        counted_of.push_back(GridFrameOf(k, fps));
      }
    }
    ASSERT_EQ(a.source_frames_size(), static_cast<int>(counted_of.size()));
    ASSERT_EQ(a.motion().frame_count(), a.source_frames_size());
    for (size_t k = 0; k < counted_of.size(); ++k) {
      const int t = counted_of[k];
      const int shown = given[static_cast<size_t>(t)];
      EXPECT_EQ(a.source_frames(static_cast<int>(k)), shown) << k;
      if (grid) EXPECT_EQ(a.grid_frames(static_cast<int>(k)), t) << k;
      const bool held = t > 0 && given[static_cast<size_t>(t - 1)] == shown;
      EXPECT_EQ(a.kinds(static_cast<int>(k)), held ? v1::HELD : v1::ORIGINAL) << k;
      for (int c = 0; c < 12; ++c) {  // a verbatim copy of the source frame
        ASSERT_EQ(a.motion().channels().values(static_cast<int>(k) * 12 + c),
                  r.motion().channels().values(shown * 12 + c));
      }
    }
    // The identity: per counted frame, the response's timing is the given one. At the timing
    // rate that is source_frames itself; at the source rate, every counted frame some output
    // frame shows (a source slower than the grid skips some) reads back its given entry.
    if (timing_rate || !grid) {
      EXPECT_EQ(std::vector<int>(a.source_frames().begin(), a.source_frames().end()), given);
    }
    EXPECT_EQ(a.omissions_applied() + a.holds_applied() + a.duplicates_applied(), 0);
    EXPECT_EQ(a.hidden_frames_size() + a.cut_frames_size() + a.input_ssd_size(), 0);
  }
}

TEST_F(GivenSkeletalTimingTest, AComputedTimingGivenBackGivesTheSameMotionBytes) {
  SplitMix64 rng(4646);
  for (int round = 0; round < 40; ++round) {
    const int fps = kRates[rng.Int(0, 4)];
    const int frames = rng.Int(8, 120);
    v1::RetimeSkeletalRequest r = RandomClip(rng, frames, fps);
    r.set_cut_neighbour_ratio(0);  // one shot: shots have grids of their own
    if (rng.OneIn(2)) r.set_keep_length(false);
    SCOPED_TRACE(::testing::Message() << "round " << round << ": " << frames << " at " << fps);
    // The computed timing per counted frame: source_frames at the timing rate.
    v1::RetimeSkeletalRequest at_timing_rate = r;
    at_timing_rate.set_output_rate(v1::TIMING_RATE);
    v1::RetimeSkeletalResponse counted;
    ASSERT_TRUE(CallRpc(server_.stub(), at_timing_rate, &counted).ok());
    for (const v1::OutputRate rate : {v1::SOURCE_RATE, v1::TIMING_RATE}) {
      v1::RetimeSkeletalRequest computed_request = r;
      computed_request.set_output_rate(rate);
      v1::RetimeSkeletalResponse computed;
      ASSERT_TRUE(CallRpc(server_.stub(), computed_request, &computed).ok());
      v1::RetimeSkeletalRequest given_request = computed_request;
      *given_request.mutable_given_timing()->mutable_source_frames() = counted.source_frames();
      v1::RetimeSkeletalResponse given;
      const grpc::Status status = CallRpc(server_.stub(), given_request, &given);
      ASSERT_TRUE(status.ok()) << status.error_message();
      EXPECT_EQ(given.motion().SerializeAsString(), computed.motion().SerializeAsString());
      EXPECT_EQ(given.source_frames().size(), computed.source_frames().size());
      EXPECT_TRUE(std::equal(given.source_frames().begin(), given.source_frames().end(),
                             computed.source_frames().begin()));
      EXPECT_TRUE(std::equal(given.grid_frames().begin(), given.grid_frames().end(),
                             computed.grid_frames().begin(), computed.grid_frames().end()));
      EXPECT_TRUE(std::equal(given.grid_source_frames().begin(), given.grid_source_frames().end(),
                             computed.grid_source_frames().begin(),
                             computed.grid_source_frames().end()));
    }
  }
}

TEST_F(GivenSkeletalTimingTest, OneTimingOnAProxyAndAFinalRigGivesOneMap) {
  // The same channels on another skeleton's offsets (a proxy and the final rig): no distance
  // is measured, so the map is the given one on both, and each motion is its own frames.
  v1::RetimeSkeletalRequest proxy = MakeSkeletalRequest(48);
  proxy.mutable_motion()->set_frame_time(1.0 / 60.0);
  // 48 frames at 60 fps: 19 grid frames.
  Give(proxy, {0, 0, 0, 7, 7, 19, 19, 19, 3, 3, 40, 40, 47, 47, 47, 47, 30, 30, 30});
  v1::RetimeSkeletalRequest final_rig = proxy;
  for (auto& joint : *final_rig.mutable_motion()->mutable_skeleton()->mutable_joints()) {
    joint.mutable_offset()->set_y(joint.offset().y() * 3.5 + 1.0);
  }
  v1::RetimeSkeletalResponse a, b;
  ASSERT_TRUE(CallRpc(server_.stub(), proxy, &a).ok());
  ASSERT_TRUE(CallRpc(server_.stub(), final_rig, &b).ok());
  EXPECT_GT(a.source_frames_size(), 40);
  EXPECT_TRUE(std::equal(a.source_frames().begin(), a.source_frames().end(),
                         b.source_frames().begin(), b.source_frames().end()));
  EXPECT_EQ(a.motion().channels().SerializeAsString(), b.motion().channels().SerializeAsString());
  EXPECT_NE(a.motion().skeleton().SerializeAsString(), b.motion().skeleton().SerializeAsString());
}

std::string ReadSample(const std::string& name) {
  std::ifstream in(std::string(KOMA_SAMPLES_DIR) + "/" + name, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Files over the wire: the BVH and the glTF a computed answer writes, written again from its
// timing given back, byte for byte.
TEST_F(GivenSkeletalTimingTest, FileAnswersGivenBackAreTheSameFiles) {
  struct Case {
    std::string name;
    v1::RetimeSkeletalRequest request;
  };
  std::vector<Case> cases;
  for (const double timing_fps : {0.0, 12.0}) {  // the pitch is 24 fps: no grid, and on twos
    v1::RetimeSkeletalRequest r;
    r.set_bvh_text(ReadSample("pitch.bvh"));
    r.set_timing_fps(timing_fps);
    cases.push_back({"pitch.bvh at " + std::to_string(timing_fps), r});
  }
  v1::RetimeSkeletalRequest gltf;
  gltf.set_gltf(::koma::testing::ArmGltf().Glb());
  cases.push_back({"arm.glb", gltf});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    v1::RetimeSkeletalRequest at_timing_rate = c.request;
    at_timing_rate.set_output_rate(v1::TIMING_RATE);
    at_timing_rate.set_return_motion(false);
    v1::RetimeSkeletalResponse counted;
    ASSERT_TRUE(CallRpc(server_.stub(), at_timing_rate, &counted).ok());
    ASSERT_GT(counted.source_frames_size(), 2);
    v1::RetimeSkeletalResponse computed;
    ASSERT_TRUE(CallRpc(server_.stub(), c.request, &computed).ok());
    v1::RetimeSkeletalRequest back = c.request;
    *back.mutable_given_timing()->mutable_source_frames() = counted.source_frames();
    v1::RetimeSkeletalResponse given;
    const grpc::Status status = CallRpc(server_.stub(), back, &given);
    ASSERT_TRUE(status.ok()) << status.error_message();
    EXPECT_TRUE(given.timing_given());
    EXPECT_EQ(given.bvh_text(), computed.bvh_text());
    EXPECT_EQ(given.gltf(), computed.gltf());
    EXPECT_FALSE(given.bvh_text().empty() && given.gltf().empty());
  }
  // A glTF request must retime exactly one animation for a timing to be given.
  v1::RetimeSkeletalRequest none = gltf;
  none.set_gltf_retime_none(true);
  none.mutable_given_timing()->add_source_frames(0);
  v1::RetimeSkeletalResponse refused;
  const grpc::Status status = CallRpc(server_.stub(), none, &refused);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(),
              ::testing::HasSubstr("given_timing: a given timing applies to one animation, but "
                                   "this request retimes 0; name one in gltf_animations"));
}

}  // namespace
}  // namespace koma::server
