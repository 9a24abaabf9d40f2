// RetimeCurves answers pinned byte for byte (re-pinned by issue 46, which adds
// DrawingTiming.drawing_source_frame: without that field the answers are the earlier bytes): the exact bytes the server sends (a generic call,
// so nothing is parsed and serialised again on the client) for fixed requests that use every
// segment type, dense samples, curve and segment overrides, tame and tsume. A change that only
// makes the server faster must leave these fingerprints as they are; a change that means to
// alter the answer updates them and says so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "convert/curves_convert.h"
#include "core/curves.h"
#include "core/split_mix64.h"
#include "koma/v1/retime.pb.h"
#include "tests/server/curves_request_builder.h"
#include "tests/server/in_process_server.h"
#include "tests/testing/fnv1a.h"

namespace koma::server {
namespace {

using ::koma::testing::Fnv1a64;

// `curves` keyframe curves over `frames` frames, keys every 5-14 frames, segment types drawn
// from all four (Beziers with handles inside their segment), plus one dense curve; ids
// "P0", "P1", ...
v1::RetimeCurvesRequest MixedRequest(int curves, int frames, uint64_t seed) {
  SplitMix64 rng(seed);
  v1::RetimeCurvesRequest request;
  v1::CurveSet* set = request.mutable_curves();
  set->set_fps(30.0);
  set->set_frame_count(frames);
  set->set_beziers_restricted(true);
  for (int c = 0; c < curves; ++c) {
    v1::Curve* curve = set->add_curves();
    curve->set_id("P" + std::to_string(c));
    ::koma::testing::AddRandomKeyframes(rng, frames, 5, 14, 0, curve);
  }
  v1::Curve* dense = set->add_curves();
  dense->set_id("Dense");
  for (int f = 0; f < frames; ++f) dense->add_samples(rng.Unit());
  return request;
}

// Sends `request_bytes` to RetimeCurves as they are (koma::testing::RawUnaryCall).
grpc::Status RawCall(koma::testing::InProcessServer& server, const std::string& request_bytes,
                     std::string* answer) {
  return koma::testing::RawUnaryCall(server, "/koma.v1.Retime/RetimeCurves", request_bytes, answer);
}

// Where every key is a key pose (source frames, no merging, whole-frame keys; the keyframe
// curves, not the dense one), drawing every key changes no drawing: each value is still the curve at its drawing's tau, but for the last
// bits of a drawing that shows a key (its exact value where a Bezier evaluated at its own key
// time may differ by an ulp). Checked to 1e-9 of each value.
void ExpectValuesAtTau(const v1::RetimeCurvesRequest& request, const std::string& bytes) {
  v1::RetimeCurvesResponse response;
  ASSERT_TRUE(response.ParseFromString(bytes));
  const absl::StatusOr<CurveSet> set = convert::CurveSetFromProto(request.curves(), "curves");
  ASSERT_TRUE(set.ok()) << set.status();
  int keys = 0;
  for (int c = 0; c < response.curves_size(); ++c) {
    const v1::RetimedCurve& curve = response.curves(c);
    // A dense curve's keys are its samples, which are no key poses: its peaks move values.
    if (set->curves[c].dense()) continue;
    const v1::DrawingTiming& timing = response.timings(curve.timing());
    keys += curve.keys_size();
    for (int f = 0; f < curve.values_size(); ++f) {
      const double want =
          EvaluateCurve(set->curves[c], timing.source_frame(f), set->beziers_restricted);
      ASSERT_NEAR(curve.values(f), want, 1e-9 * std::max(1.0, std::fabs(want)))
          << curve.id() << " frame " << f;
    }
  }
  EXPECT_GT(keys, 0);
}

// The raw bytes the server answers for `request` (the call must succeed).
std::string AnswerBytes(koma::testing::InProcessServer& server,
                        const v1::RetimeCurvesRequest& request) {
  std::string bytes;
  const grpc::Status status = RawCall(server, request.SerializeAsString(), &bytes);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return bytes;
}

// Counted in source frames (timing_fps 0), every keyframe time a key pose (merge_key_poses
// false): every key is a key pose, so each value is the curve at its drawing's tau as before the
// film grid, key-pose merging and key drawing (to the last bits; pinned again by issue 40, which
// adds `keys`).
TEST(CurvesGoldenTest, DefaultOptionsAnswerTheSameBytes) {
  koma::testing::InProcessServer server;
  v1::RetimeCurvesRequest request = MixedRequest(12, 300, 1);
  request.set_timing_fps(0.0);
  request.set_merge_key_poses(false);
  const std::string bytes = AnswerBytes(server, request);
  ExpectValuesAtTau(request, bytes);
  EXPECT_EQ(bytes.size(), 120938u);
  EXPECT_EQ(Fnv1a64(bytes), 3348426551331241719ULL);
}

// The same 30 fps curves on the 24 fps film grid, every keyframe time a key pose; and the same
// curves declared at 24 fps (no grid) answer what they answered before the grid existed.
TEST(CurvesGoldenTest, FilmGridAnswersArePinned) {
  koma::testing::InProcessServer server;
  v1::RetimeCurvesRequest unmerged = MixedRequest(12, 300, 1);
  unmerged.set_merge_key_poses(false);
  const std::string grid = AnswerBytes(server, unmerged);
  // Changed by issue 40 on purpose: key poses show their own times, every key is drawn.
  EXPECT_EQ(grid.size(), 108459u);
  EXPECT_EQ(Fnv1a64(grid), 13040335558170620256ULL);
  v1::RetimeCurvesRequest at24 = MixedRequest(12, 300, 1);
  at24.mutable_curves()->set_fps(24.0);
  v1::RetimeCurvesRequest at24_no_grid = at24;
  at24_no_grid.set_timing_fps(0.0);
  EXPECT_EQ(AnswerBytes(server, at24), AnswerBytes(server, at24_no_grid));
}

TEST(CurvesGoldenTest, OverridesTameAndTsumeAnswerTheSameBytes) {
  koma::testing::InProcessServer server;
  v1::RetimeCurvesRequest request = MixedRequest(8, 240, 2);
  request.set_timing_fps(0.0);
  request.set_merge_key_poses(false);
  request.set_frames_per_drawing(2);
  request.set_tame(1.4);
  request.set_tsume(1.25);
  v1::CurveOverride* own = request.add_curve_overrides();
  own->set_curve_id("P3");
  own->set_frames_per_drawing(3);
  own = request.add_curve_overrides();
  own->set_curve_id("Dense");
  own->set_frames_per_drawing(1);
  v1::SegmentOverride* segment = request.add_segment_overrides();
  segment->set_segment(1);
  segment->set_frames_per_drawing(4);
  segment->set_tsume(2.0);
  const std::string bytes = AnswerBytes(server, request);
  ExpectValuesAtTau(request, bytes);
  EXPECT_EQ(bytes.size(), 75596u);
  EXPECT_EQ(Fnv1a64(bytes), 2126682062598705441ULL);
}

// The defaults since key-pose merging (issue 29): keyframes closer than a drawing form one key
// pose, on the grid and in source frames, and the same request with Live2D ids in timing
// groups. The merged answers differ from the unmerged ones above on purpose: these 12 curves'
// keyframe union has a key every frame or two.
TEST(CurvesGoldenTest, MergedKeyPosesAndGroupsArePinned) {
  koma::testing::InProcessServer server;
  const std::string grid = AnswerBytes(server, MixedRequest(12, 300, 1));
  // Changed by issue 40 on purpose: every key drawn, key poses at their own times.
  EXPECT_EQ(grid.size(), 70935u);
  EXPECT_EQ(Fnv1a64(grid), 10423263193455877647ULL);
  v1::RetimeCurvesRequest frames = MixedRequest(12, 300, 1);
  frames.set_timing_fps(0.0);
  const std::string source = AnswerBytes(server, frames);
  EXPECT_EQ(source.size(), 75619u);
  EXPECT_EQ(Fnv1a64(source), 8678024445457953433ULL);
  v1::RetimeCurvesRequest grouped = MixedRequest(12, 300, 1);
  const char* ids[] = {"ParamAngleX", "ParamBodyAngleX", "ParamArmLA",    "ParamHandL",
                       "ParamHairFront", "ParamHairBack", "ParamEyeLOpen", "ParamEyeROpen",
                       "ParamMouthOpenY", "ParamBrowLY", "ParamCheek", "ParamBreath"};
  for (int c = 0; c < 12; ++c) grouped.mutable_curves()->mutable_curves(c)->set_id(ids[c]);
  grouped.set_frames_per_drawing(3);
  v1::CurveTimingGroup* hair = grouped.add_timing_groups();
  hair->set_name("hair");
  hair->add_ids("ParamHair*");
  hair->set_frames_per_drawing(2);
  v1::CurveTimingGroup* face = grouped.add_timing_groups();
  face->set_name("face");
  face->add_ids("ParamEye*");
  face->add_ids("ParamMouth*");
  face->add_ids("ParamBrow*");
  face->set_tame(1.5);
  const std::string groups = AnswerBytes(server, grouped);
  EXPECT_EQ(groups.size(), 79117u);
  EXPECT_EQ(Fnv1a64(groups), 2771909451714685427ULL);
}

// RetimeCurves parses its own request (a raw method): bytes that are no request get
// INVALID_ARGUMENT naming the message, and the server goes on answering.
TEST(CurvesGoldenTest, GarbageBytesGetInvalidArgument) {
  koma::testing::InProcessServer server;
  std::string answer;
  const grpc::Status status = RawCall(server, std::string(100, '\xff'), &answer);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("koma.v1.RetimeCurvesRequest"), std::string::npos)
      << status.error_message();
  EXPECT_FALSE(AnswerBytes(server, MixedRequest(2, 40, 3)).empty());
}

}  // namespace
}  // namespace koma::server
