// A given LipBlink timing (docs/semantics.md, "A given timing") through an in-process channel
// to the real service: bad given holds and blinks refused naming the field and value; random
// given holds and blinks come back unchanged (the identity) and paint the curves at their
// levels (checked by hand without a grid); a computed answer's holds and blinks given back
// give the same curves.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/split_mix64.h"
#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"
#include "tests/server/bad_request_table.h"
#include "tests/server/in_process_server.h"
#include "tests/server/lip_blink_request_builder.h"

namespace koma::server {
namespace {

using ::koma::testing::CallRpc;
using ::koma::testing::InProcessServer;
using ::koma::testing::MakeLipBlinkRequest;
using BadRequest = ::koma::testing::BadRequest<v1::LipBlinkRequest>;

v1::MouthHold* AddHold(v1::GivenMouthTiming* track, int begin, int length, v1::MouthShape shape) {
  v1::MouthHold* h = track->add_holds();
  h->set_begin(begin);
  h->set_length(length);
  h->set_shape(shape);
  return h;
}

v1::Blink* AddBlink(v1::GivenEyeTiming* track, int closing, int closed, int closed_end, int span,
                    int hold) {
  v1::Blink* b = track->add_blinks();
  b->set_closing_begin(closing);
  b->set_closed_begin(closed);
  b->set_closed_end(closed_end);
  b->set_open_span(span);
  b->set_hold(hold);
  return b;
}

// The valid request: MakeLipBlinkRequest (60 frames at 30 fps: 48 grid frames) with a given
// mouth and both eyes.
v1::LipBlinkRequest ValidGiven() {
  v1::LipBlinkRequest r = MakeLipBlinkRequest();
  v1::GivenMouthTiming* mouth = r.mutable_given_timing()->add_mouths();
  mouth->set_id("ParamMouthOpenY");
  AddHold(mouth, 8, 3, v1::MOUTH_OPEN);
  AddHold(mouth, 11, 3, v1::MOUTH_MID);
  AddHold(mouth, 20, 2, v1::MOUTH_OPEN);
  for (const char* id : {"ParamEyeROpen", "ParamEyeLOpen"}) {  // any order
    v1::GivenEyeTiming* eye = r.mutable_given_timing()->add_eyes();
    eye->set_id(id);
    AddBlink(eye, 15, 16, 17, 3, 2);
    AddBlink(eye, 30, 30, 30, 0, 1);
  }
  return r;
}

std::vector<BadRequest> BadRequests() {
  using C = grpc::StatusCode;
  const C kInvalid = C::INVALID_ARGUMENT;
  const auto mouth = [](v1::LipBlinkRequest& r) {
    return r.mutable_given_timing()->mutable_mouths(0);
  };
  const auto eye = [](v1::LipBlinkRequest& r) { return r.mutable_given_timing()->mutable_eyes(0); };
  return {
      {"UnknownMouth", [&](auto& r) { mouth(r)->set_id("ParamMouthForm"); }, kInvalid,
       "given_timing.mouths[0].id: \"ParamMouthForm\" is not a mouth curve (they are "
       "ParamMouthOpenY)"},
      {"MouthTwice", [&](auto& r) { *r.mutable_given_timing()->add_mouths() = *mouth(r); },
       kInvalid, "given_timing.mouths[1].id: \"ParamMouthOpenY\" is already given_timing.mouths[0]"},
      {"EyeMissing", [&](auto& r) { r.mutable_given_timing()->mutable_eyes()->RemoveLast(); },
       kInvalid,
       "given_timing.eyes: no timing for eye curve \"ParamEyeLOpen\"; give every eye curve one"},
      {"HoldLengthZero", [&](auto& r) { mouth(r)->mutable_holds(1)->set_length(0); }, kInvalid,
       "given_timing.mouths[0].holds[1].length: 0 must be >= 1"},
      {"HoldsOverlap", [&](auto& r) { mouth(r)->mutable_holds(1)->set_begin(10); }, kInvalid,
       "given_timing.mouths[0].holds[1]: begins at 10, before given_timing.mouths[0].holds[0] "
       "ends (8 + 3 frames)"},
      {"HoldPastTheEnd", [&](auto& r) { mouth(r)->mutable_holds(2)->set_begin(47); }, kInvalid,
       "given_timing.mouths[0].holds[2]: frames [47, 49) are not within the clip's 48 frames"},
      {"HoldNegative", [&](auto& r) { mouth(r)->mutable_holds(0)->set_begin(-1); }, kInvalid,
       "given_timing.mouths[0].holds[0]: frames [-1, 2) are not within"},
      {"ShapeUnspecified",
       [&](auto& r) { mouth(r)->mutable_holds(2)->set_shape(v1::MOUTH_SHAPE_UNSPECIFIED); },
       kInvalid, "given_timing.mouths[0].holds[2].shape: 0 is not a mouth drawing"},
      {"BlinkHold4", [&](auto& r) { eye(r)->mutable_blinks(0)->set_hold(4); }, kInvalid,
       "given_timing.eyes[0].blinks[0].hold: 4 must be 1, 2 or 3"},
      {"BlinkSpanNegative", [&](auto& r) { eye(r)->mutable_blinks(1)->set_open_span(-2); },
       kInvalid, "given_timing.eyes[0].blinks[1].open_span: -2 must be within 0 .. the clip's 48"},
      {"BlinkSpanHuge", [&](auto& r) { eye(r)->mutable_blinks(1)->set_open_span(2147483647); },
       kInvalid, "given_timing.eyes[0].blinks[1].open_span: 2147483647 must be within 0"},
      {"BlinkReversed", [&](auto& r) { eye(r)->mutable_blinks(0)->set_closed_end(15); }, kInvalid,
       "given_timing.eyes[0].blinks[0]: closing_begin 15, closed_begin 16, closed_end 15 must be "
       "in order within the clip's 48 frames"},
      {"BlinkPastTheEnd", [&](auto& r) { eye(r)->mutable_blinks(1)->set_closed_end(48); },
       kInvalid, "closed_end 48 must be in order within the clip's 48 frames"},
      {"BlinksOutOfOrder", [&](auto& r) { eye(r)->mutable_blinks(1)->set_closing_begin(17); },
       kInvalid,
       "given_timing.eyes[0].blinks[1].closing_begin: 17 is not after "
       "given_timing.eyes[0].blinks[0].closed_end 17"},
      {"WithAVoice", [&](auto& r) { r.set_rhubarb_cues("0.00\tX\n"); }, kInvalid,
       "given_timing: not with a voice (audio, rhubarb_cues) or spine_json"},
      {"NoGrid",  // without a grid the clip has 60 frames: a hold at 47 fits, one at 59 + 2 not
       [&](auto& r) {
         r.set_timing_fps(0);
         mouth(r)->mutable_holds(2)->set_begin(59);
       },
       kInvalid, "given_timing.mouths[0].holds[2]: frames [59, 61) are not within the clip's 60"},
  };
}

class GivenLipBlinkBadRequestTest
    : public koma::testing::BadRequestSuite<GivenLipBlinkBadRequestTest, v1::LipBlinkRequest> {
 public:
  static server::ServerConfig SuiteConfig() { return InProcessServer::Config(1, 50'000); }
  static v1::LipBlinkRequest ValidRequest() { return ValidGiven(); }
};

TEST_P(GivenLipBlinkBadRequestTest, AnswersCodeAndNamesTheField) { ExpectTheRowRefused(); }
INSTANTIATE_TEST_SUITE_P(Table, GivenLipBlinkBadRequestTest, ::testing::ValuesIn(BadRequests()),
                         ::koma::testing::RowName());
TEST(GivenLipBlinkBadRequestTableTest, TheValidRequestIsAccepted) {
  InProcessServer server(GivenLipBlinkBadRequestTest::SuiteConfig());
  ::koma::testing::ExpectAccepted(server.stub(), ValidGiven());
}

constexpr int kRates[] = {24, 12, 30, 60};
int CountedFrames(int frames, int fps) {
  return fps == 24 ? frames : static_cast<int>((int64_t{24} * (frames - 1)) / fps) + 1;
}

// A talking, blinking clip of `frames` frames at `fps` (as grid_identity_test's).
v1::LipBlinkRequest RandomClip(SplitMix64& rng, int frames, int fps) {
  v1::LipBlinkRequest request;
  v1::CurveSet* set = request.mutable_curves();
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
  if (rng.OneIn(3)) request.mutable_eyes()->set_linked(false);
  if (rng.OneIn(3)) request.mutable_eyes()->set_max(1.0);
  if (rng.OneIn(3)) {
    request.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
    request.mutable_eyes()->mutable_auto_blink()->set_mean_interval_s(0.5 + rng.Unit());
  }
  return request;
}

class GivenLipBlinkTimingTest : public ::testing::Test {
 protected:
  InProcessServer server_{InProcessServer::Config(2, 1'000'000)};
};

TEST_F(GivenLipBlinkTimingTest, GivenHoldsAndBlinksComeBackUnchangedAndPaintTheCurves) {
  SplitMix64 rng(4601);
  for (int round = 0; round < 80; ++round) {
    const int fps = kRates[rng.Int(0, 3)];
    const int frames = rng.Int(fps / 12 + 3, 200);
    v1::LipBlinkRequest r = RandomClip(rng, frames, fps);
    const int counted = CountedFrames(frames, fps);
    v1::GivenLipBlinkTiming* given = r.mutable_given_timing();
    v1::GivenMouthTiming* mouth = given->add_mouths();
    mouth->set_id("ParamMouthOpenY");
    for (int f = rng.Int(0, 5); f < counted;) {
      const int length = std::min(rng.Int(1, 6), counted - f);
      AddHold(mouth, f, length, static_cast<v1::MouthShape>(rng.Int(1, 3)));
      f += length + (rng.OneIn(3) ? rng.Int(1, 10) : 0);
    }
    for (const char* id : {"ParamEyeLOpen", "ParamEyeROpen"}) {
      v1::GivenEyeTiming* eye = given->add_eyes();
      eye->set_id(id);
      for (int f = rng.Int(0, 10); f + 3 < counted; f += rng.Int(1, 20)) {
        const int closed = f + rng.Int(0, 2);
        const int closed_end = std::min(counted - 1, closed + rng.Int(0, 3));
        AddBlink(eye, f, closed, closed_end, rng.Int(0, 4), rng.Int(1, 3))
            ->set_automatic(rng.OneIn(3));
        f = closed_end;
      }
    }
    SCOPED_TRACE(::testing::Message() << "round " << round << ": " << frames << " frames at "
                                      << fps << " fps");
    v1::LipBlinkResponse a;
    const grpc::Status status = CallRpc(server_.stub(), r, &a);
    ASSERT_TRUE(status.ok()) << status.error_message();
    ASSERT_EQ(a.mouths_size(), 1);
    EXPECT_TRUE(a.mouths(0).given());
    EXPECT_EQ(a.mouths(0).holds().size(), mouth->holds().size());
    for (int h = 0; h < mouth->holds_size(); ++h) {
      EXPECT_EQ(a.mouths(0).holds(h).SerializeAsString(), mouth->holds(h).SerializeAsString());
    }
    ASSERT_EQ(a.eyes_size(), 2);
    for (int e = 0; e < 2; ++e) {
      EXPECT_TRUE(a.eyes(e).given());
      const v1::GivenEyeTiming& g = given->eyes(e);
      ASSERT_EQ(a.eyes(e).id(), g.id());
      ASSERT_EQ(a.eyes(e).blinks_size(), g.blinks_size());
      for (int b = 0; b < g.blinks_size(); ++b) {
        EXPECT_EQ(a.eyes(e).blinks(b).SerializeAsString(), g.blinks(b).SerializeAsString());
      }
    }
    if (fps != 24) continue;
    // Without a grid, by hand: the mouth at each hold's level, its input elsewhere; each eye
    // at its closed level from closed_begin through closed_end.
    const v1::ConvertedCurve& m = a.curves(0);
    std::vector<double> expected(r.curves().curves(0).samples().begin(),
                                 r.curves().curves(0).samples().end());
    for (const v1::MouthHold& h : mouth->holds()) {
      const double level = h.shape() == v1::MOUTH_CLOSED ? a.mouths(0).closed_level()
                           : h.shape() == v1::MOUTH_MID  ? a.mouths(0).mid_level()
                                                         : a.mouths(0).open_level();
      for (int f = h.begin(); f < h.begin() + h.length(); ++f) expected[f] = level;
    }
    EXPECT_EQ(std::vector<double>(m.values().begin(), m.values().end()), expected);
    for (int e = 0; e < 2; ++e) {
      const v1::ConvertedCurve& c = a.curves(1 + e);
      for (const v1::Blink& b : given->eyes(e).blinks()) {
        for (int f = b.closed_begin(); f <= b.closed_end(); ++f) {
          EXPECT_EQ(c.values(f), a.eyes(e).closed_level()) << c.id() << " frame " << f;
        }
      }
    }
  }
}

TEST_F(GivenLipBlinkTimingTest, AComputedTimingGivenBackGivesTheSameCurves) {
  SplitMix64 rng(4602);
  for (int round = 0; round < 60; ++round) {
    const int fps = kRates[rng.Int(0, 3)];
    const int frames = rng.Int(fps / 12 + 3, 300);
    v1::LipBlinkRequest r = RandomClip(rng, frames, fps);
    SCOPED_TRACE(::testing::Message() << "round " << round << ": " << frames << " at " << fps);
    v1::LipBlinkResponse computed;
    ASSERT_TRUE(CallRpc(server_.stub(), r, &computed).ok());
    v1::LipBlinkRequest back = r;
    for (const v1::MouthTrack& m : computed.mouths()) {
      v1::GivenMouthTiming* g = back.mutable_given_timing()->add_mouths();
      g->set_id(m.id());
      *g->mutable_holds() = m.holds();
    }
    for (const v1::EyeTrack& e : computed.eyes()) {
      v1::GivenEyeTiming* g = back.mutable_given_timing()->add_eyes();
      g->set_id(e.id());
      *g->mutable_blinks() = e.blinks();
    }
    v1::LipBlinkResponse given;
    const grpc::Status status = CallRpc(server_.stub(), back, &given);
    ASSERT_TRUE(status.ok()) << status.error_message();
    // Identical but for the `given` marks and, for speech intervals that touch, the mouth's
    // speech (the holds' union joins them).
    for (auto& m : *given.mutable_mouths()) {
      EXPECT_TRUE(m.given());
      m.clear_given();
    }
    for (auto& e : *given.mutable_eyes()) {
      EXPECT_TRUE(e.given());
      e.clear_given();
    }
    for (int i = 0; i < computed.mouths_size(); ++i) {
      given.mutable_mouths(i)->clear_speech();
      computed.mutable_mouths(i)->clear_speech();
    }
    EXPECT_EQ(given.SerializeAsString(), computed.SerializeAsString());
  }
}

}  // namespace
}  // namespace koma::server
