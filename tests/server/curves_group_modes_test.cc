// RetimeCurves' group modes (docs/semantics.md, "Group modes") through an in-process channel:
// a GROUP_LIP_BLINK group's mouth and eyes against the LipBlink RPC's answer on the same
// curves, byte for byte where the mouth and eyes are still outside speech and blinks, and
// against a naive reference of "LipBlink's drawing where it repaints, the group's drawing
// elsewhere" on generated motions whose eyes ease back open; GROUP_KEEP curves against the
// input (values, and the keyframes of a file answer); the other groups unchanged by a group's
// mode; bad mode fields.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "convert/curve_text.h"
#include "convert/curves_convert.h"
#include "core/curves.h"
#include "core/film_grid.h"
#include "core/lip_blink.h"
#include "core/lip_blink_grid.h"
#include "koma/v1/retime.pb.h"
#include "server/curves_request.h"
#include "tests/server/in_process_server.h"
#include "tests/testing/live2d_motion.h"

namespace koma::server {
namespace {

using koma::testing::CallRpc;
using koma::testing::InProcessServer;

std::string ReadSample(const std::string& name) {
  std::ifstream in(std::string(KOMA_SAMPLES_DIR) + "/" + name, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

v1::CurveSet SampleCurves(const std::string& name) {
  return convert::CurveSetToProto(convert::ParseCurveText(ReadSample(name), false, 30).value().curves);
}

v1::CurveSet GeneratedCurves(double fps, int curves, uint64_t seed) {
  return convert::CurveSetToProto(koma::testing::Live2dMotion({fps, curves, 4.0, seed}));
}

// The raw bytes the service answers, parsed, after checking they are the message path's.
v1::RetimeCurvesResponse Retime(InProcessServer& server, const v1::RetimeCurvesRequest& request) {
  std::string bytes;
  const grpc::Status status = koma::testing::RawUnaryCall(
      server, "/koma.v1.Retime/RetimeCurves", request.SerializeAsString(), &bytes);
  EXPECT_TRUE(status.ok()) << status.error_message();
  v1::RetimeCurvesResponse want;
  EXPECT_TRUE(HandleRetimeCurves(request, RequestLimits(), &want).ok());
  EXPECT_EQ(bytes, want.SerializeAsString());
  v1::RetimeCurvesResponse got;
  EXPECT_TRUE(got.ParseFromString(bytes));
  return got;
}

// The LipBlink RPC on the curves of `set` whose ids `in_group` accepts, with these settings.
v1::LipBlinkResponse LipBlinkOn(InProcessServer& server, const v1::CurveSet& set,
                                const std::set<std::string>& in_group, v1::MouthSettings mouth,
                                const v1::EyeSettings& eyes, std::optional<uint64_t> seed,
                                double timing_fps) {
  v1::LipBlinkRequest request;
  v1::CurveSet* group = request.mutable_curves();
  *group = set;
  group->clear_curves();
  for (const v1::Curve& c : set.curves()) {
    if (in_group.count(c.id())) *group->add_curves() = c;
  }
  *request.mutable_mouth() = mouth;
  *request.mutable_eyes() = eyes;
  if (seed) request.set_seed(*seed);
  request.set_timing_fps(timing_fps);
  v1::LipBlinkResponse response;
  const grpc::Status status = CallRpc(server.stub(), request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return response;
}

const v1::RetimedCurve& CurveOf(const v1::RetimeCurvesResponse& response, const std::string& id) {
  for (const v1::RetimedCurve& c : response.curves()) {
    if (c.id() == id) return c;
  }
  ADD_FAILURE() << "no curve " << id;
  return v1::RetimedCurve::default_instance();
}

std::set<std::string> GroupIds(const v1::RetimeCurvesResponse& response, const std::string& name) {
  std::set<std::string> ids;
  for (const v1::CurveTimingGroupResult& g : response.timing_groups()) {
    if (g.name() != name) continue;
    for (int c : g.curves()) ids.insert(response.curves(c).id());
  }
  return ids;
}

std::vector<double> Values(const v1::RetimedCurve& c) { return {c.values().begin(), c.values().end()}; }

// The default grouping on samples/talk_blink.motion3.json (the face group in GROUP_LIP_BLINK:
// ParamMouthOpenY, ParamEyeLOpen, ParamEyeROpen), on the default 24 fps grid, on threes, twos
// and ones: each drawn curve is exactly the LipBlink RPC's curve on the face group's curves
// (values and stepped keyframes, byte for byte: on this grid the sample's mouth and eyes are
// still wherever LipBlink leaves them), and each eye curve shows three values. (Counted in
// source frames, the right eye eases back open after LipBlink's repaint; there the next test's
// rule applies.)
TEST(CurvesGroupModesTest, LipBlinkGroupIsTheLipBlinkRpcsAnswerOnTheSample) {
  InProcessServer server;
  const v1::CurveSet set = SampleCurves("talk_blink.motion3.json");
  for (double timing_fps : {24.0}) {
    for (int n : {3, 2, 1}) {
      v1::RetimeCurvesRequest request;
      *request.mutable_curves() = set;
      request.set_timing_fps(timing_fps);
      request.set_frames_per_drawing(n);
      const v1::RetimeCurvesResponse response = Retime(server, request);
      const std::set<std::string> face = GroupIds(response, "face");
      ASSERT_EQ(face.size(), 3u);
      v1::MouthSettings mouth;
      mouth.set_frames_per_shape(n);  // the group's n, as an unset frames_per_shape takes
      const v1::LipBlinkResponse lip = LipBlinkOn(server, set, face, mouth, v1::EyeSettings(),
                                                  std::nullopt, timing_fps);
      ASSERT_EQ(lip.curves_size(), 3);
      for (const v1::ConvertedCurve& want : lip.curves()) {
        const v1::RetimedCurve& got = CurveOf(response, want.id());
        EXPECT_EQ(got.values().size(), want.values().size());
        for (int k = 0; k < want.values_size(); ++k) {
          ASSERT_EQ(std::memcmp(got.values().data() + k, want.values().data() + k, sizeof(double)), 0)
              << want.id() << " frame " << k << " at " << timing_fps << " fps, on " << n;
        }
        EXPECT_EQ(got.stepped().SerializeAsString(), want.stepped().SerializeAsString())
            << want.id() << " at " << timing_fps << " fps, on " << n;
        EXPECT_EQ(got.hold_histogram_size(), 0) << want.id();
        if (want.id() != "ParamMouthOpenY") {
          const std::vector<double> v = Values(got);
          EXPECT_LE(std::set<double>(v.begin(), v.end()).size(), 3u) << want.id();
        }
      }
      // The body (ParamAngleX) is stepped on its own key poses as before.
      EXPECT_GT(CurveOf(response, "ParamAngleX").hold_histogram_size(), 0);
    }
  }
}

// A request group in GROUP_LIP_BLINK with its own mouth and eye settings and seed: the
// LipBlink RPC with the same settings on the group's curves answers the same drawings.
TEST(CurvesGroupModesTest, LipBlinkGroupTakesItsOwnSettings) {
  InProcessServer server;
  const v1::CurveSet set = SampleCurves("talk_blink.motion3.json");
  v1::RetimeCurvesRequest request;
  *request.mutable_curves() = set;
  v1::CurveTimingGroup* g = request.add_timing_groups();
  g->set_name("talk");
  g->add_ids("ParamMouth*");
  g->add_ids("ParamEye?Open");
  g->set_mode(v1::GROUP_LIP_BLINK);
  g->set_frames_per_drawing(2);
  g->mutable_mouth()->set_mode(v1::MOUTH_FOLLOW);
  g->mutable_mouth()->set_frames_per_shape(3);
  g->mutable_eyes()->set_mid_ratio(0.4);
  g->mutable_eyes()->add_ids("ParamEyeLOpen");  // the right eye is only stepped
  g->set_seed(7);
  const v1::RetimeCurvesResponse response = Retime(server, request);
  const v1::LipBlinkResponse lip =
      LipBlinkOn(server, set, GroupIds(response, "talk"), g->mouth(), g->eyes(), 7, 24.0);
  ASSERT_EQ(lip.curves_size(), 2);
  for (const v1::ConvertedCurve& want : lip.curves()) {
    const v1::RetimedCurve& got = CurveOf(response, want.id());
    EXPECT_EQ(Values(got), std::vector<double>(want.values().begin(), want.values().end()))
        << want.id();
    EXPECT_EQ(got.stepped().SerializeAsString(), want.stepped().SerializeAsString()) << want.id();
  }
  // ParamEyeROpen is not LipBlink's here: stepped on twos with the group.
  const v1::RetimedCurve& right = CurveOf(response, "ParamEyeROpen");
  EXPECT_GT(right.hold_histogram_size(), 0);
  EXPECT_EQ(response.timings(right.timing()).frames_per_drawing(), 2);
}

// Per source frame: LipBlink repaints it (speech, a blink's repaint, the grid frame before).
std::vector<bool> RepaintedFrames(const v1::LipBlinkResponse& lip, const std::string& id,
                                  const std::optional<FilmGrid>& grid, int frames) {
  const int grid_frames = grid ? grid->GridFrameCount(frames) : frames;
  std::vector<bool> mask(static_cast<size_t>(grid_frames), false);
  for (const v1::MouthTrack& m : lip.mouths()) {
    if (m.id() != id) continue;
    std::vector<FrameInterval> speech;
    for (const v1::FrameInterval& i : m.speech()) speech.push_back({i.begin(), i.end()});
    mask = SpeechMask(speech, grid_frames);
  }
  for (const v1::EyeTrack& e : lip.eyes()) {
    if (e.id() != id) continue;
    std::vector<Blink> blinks;
    for (const v1::Blink& b : e.blinks()) {
      blinks.push_back({b.closing_begin(), b.closed_begin(), b.closed_end(), b.open_span(),
                        b.hold(), b.automatic()});
    }
    mask = BlinkMask(blinks, grid_frames);
  }
  return grid ? RepaintedSourceFrames(mask, *grid, frames) : mask;
}

// Generated motions (40-80 curves, blinks easing back open over Bezier segments, a talking
// mouth; 30 and 60 fps; on the 24 fps grid and in source frames) and the sample counted in
// source frames: wherever LipBlink repaints, the drawn curve is the LipBlink RPC's;
// everywhere else it holds, for each frame, the input at the source frame nearest its
// drawing's tau, kept inside the stretch LipBlink left (a naive reference over the raw input
// and the group's timing). So the eyes no longer drift smoothly: within a run of one drawing
// the value never changes.
TEST(CurvesGroupModesTest, LipBlinkGroupHoldsTheGroupsDrawingsOutsideRepaints) {
  InProcessServer server;
  int frames_checked = 0, held_differs = 0;
  std::vector<std::pair<v1::CurveSet, double>> cases;  // the motion and the grid
  for (double fps : {30.0, 60.0}) {
    for (uint64_t seed = 1; seed <= 4; ++seed) {
      cases.push_back({GeneratedCurves(fps, 40 + 10 * static_cast<int>(seed), seed),
                       seed % 2 == 0 ? 0.0 : 24.0});
    }
  }
  cases.push_back({SampleCurves("talk_blink.motion3.json"), 0.0});
  for (const auto& [set, timing_fps] : cases) {
    const double fps = set.fps();
    {
      v1::RetimeCurvesRequest request;
      *request.mutable_curves() = set;
      request.set_timing_fps(timing_fps);
      const v1::RetimeCurvesResponse response = Retime(server, request);
      const std::set<std::string> face = GroupIds(response, "face");
      v1::MouthSettings mouth;
      mouth.set_frames_per_shape(3);
      const v1::LipBlinkResponse lip =
          LipBlinkOn(server, set, face, mouth, v1::EyeSettings(), std::nullopt, timing_fps);
      const std::optional<FilmGrid> grid = FilmGrid::Make(fps, timing_fps);
      const CurveSet core = convert::CurveSetFromProto(set, "curves").value();
      for (const v1::ConvertedCurve& want : lip.curves()) {
        const v1::RetimedCurve& got = CurveOf(response, want.id());
        const int frames = want.values_size();
        ASSERT_EQ(got.values_size(), frames);
        const std::vector<bool> repainted = RepaintedFrames(lip, want.id(), grid, frames);
        const Curve* input = nullptr;
        for (const Curve& c : core.curves) {
          if (c.id == want.id()) input = &c;
        }
        ASSERT_NE(input, nullptr);
        const std::vector<double> raw = SampleEveryFrame(*input, frames, core.beziers_restricted);
        const v1::DrawingTiming& timing = response.timings(got.timing());
        for (int k = 0; k < frames; ++k) {
          if (repainted[k]) {
            ASSERT_EQ(got.values(k), want.values(k)) << want.id() << " frame " << k;
            continue;
          }
          int begin = k, end = k + 1;
          while (begin > 0 && !repainted[begin - 1]) --begin;
          while (end < frames && !repainted[end]) ++end;
          const int nearest = static_cast<int>(std::floor(timing.source_frame(k) + 0.5));
          const int from = std::min(std::max(nearest, begin), end - 1);
          ASSERT_EQ(got.values(k), raw[from]) << want.id() << " frame " << k << " at " << fps << " fps, grid " << timing_fps;
          held_differs += got.values(k) != want.values(k);  // LipBlink keeps the input there
          if (k > begin && timing.drawing_of_frame(k) == timing.drawing_of_frame(k - 1)) {
            ASSERT_EQ(got.values(k), got.values(k - 1)) << want.id() << " frame " << k;
          }
          ++frames_checked;
        }
        // The stepped keyframes give back the values at every frame (stepped: the last point
        // at or before k).
        const std::vector<CurvePoint> steps = convert::StepsFromProto(got.stepped());
        size_t p = 0;
        for (int k = 0; k < frames; ++k) {
          while (p + 1 < steps.size() && steps[p + 1].frame <= k) ++p;
          ASSERT_EQ(steps[p].value, got.values(k)) << want.id() << " frame " << k;
        }
      }
    }
  }
  EXPECT_GT(frames_checked, 1000);
  EXPECT_GT(held_differs, 0);  // the motions do ease outside LipBlink's repaints
}

// Eyes keyed at 1 between blinks with a brief overshoot to 1.2, as Haru's m04 (issue 40), then a
// squint held at 0.8 with a blink inside it; the right eye at 0.97 of the left and a frame
// later. 30 fps, 6 s. Before, E_max (1.2) was every blink's open drawing and 1 never counted as
// open, so the eyes were drawn at 1.2 nearly the whole clip and the squint around its blink at
// 1.2 too (docs/semantics.md, "LipBlink", "Open levels").
v1::CurveSet WideEyedMotion() {
  std::vector<double> left(30, 1.0);
  const auto add = [&left](std::vector<double> part) {
    left.insert(left.end(), part.begin(), part.end());
  };
  add({0.6, 0.2, 0.0, 0.0, 0.3, 0.7});  // blink A, frames 30-35
  add(std::vector<double>(24, 1.0));
  add({1.05, 1.12, 1.18, 1.2, 1.2, 1.18, 1.12, 1.05});  // the overshoot, frames 60-67
  add(std::vector<double>(22, 1.0));
  add({0.96, 0.92, 0.88, 0.84});        // into the squint, frames 90-93
  add(std::vector<double>(16, 0.8));    // held from 94
  add({0.5, 0.2, 0.0, 0.0, 0.3, 0.6});  // blink B, frames 110-115
  add(std::vector<double>(24, 0.8));
  add({0.84, 0.88, 0.92, 0.96});  // out of it, frames 140-143
  add(std::vector<double>(36, 1.0));
  v1::CurveSet set;
  set.set_fps(30.0);
  set.set_frame_count(static_cast<int>(left.size()));
  v1::Curve* mouth = set.add_curves();
  mouth->set_id("ParamMouthOpenY");
  for (size_t f = 0; f < left.size(); ++f) mouth->add_samples(0.0);
  for (int eye = 0; eye < 2; ++eye) {
    v1::Curve* curve = set.add_curves();
    curve->set_id(eye == 0 ? "ParamEyeLOpen" : "ParamEyeROpen");
    for (size_t f = 0; f < left.size(); ++f) {
      curve->add_samples(eye == 0 ? left[f] : 0.97 * left[f == 0 ? 0 : f - 1]);
    }
  }
  v1::Curve* angle = set.add_curves();
  angle->set_id("ParamAngleX");
  for (size_t f = 0; f < left.size(); ++f) angle->add_samples(0.1 * static_cast<double>(f));
  return set;
}

// The LipBlink RPC and a GROUP_LIP_BLINK face group of RetimeCurves (the default grouping) on
// the 24 fps grid, on threes: the eyes are drawn at their level, 1 (0.97), wherever the input
// is; only the frames around the overshoot show more. Inside the squint the blink closes from
// 0.8, is half-open at 0.4 and reopens to 0.8. The group shows LipBlink's values wherever
// LipBlink repaints.
TEST(CurvesGroupModesTest, EyesReopenToTheAnimatorsLevelOnTheRpcAndInTheFaceGroup) {
  InProcessServer server;
  const v1::CurveSet set = WideEyedMotion();
  v1::RetimeCurvesRequest request;
  *request.mutable_curves() = set;
  const v1::RetimeCurvesResponse response = Retime(server, request);
  const std::set<std::string> face = GroupIds(response, "face");
  ASSERT_EQ(face.size(), 3u);
  v1::MouthSettings mouth;
  mouth.set_frames_per_shape(3);
  const v1::LipBlinkResponse lip =
      LipBlinkOn(server, set, face, mouth, v1::EyeSettings(), std::nullopt, 24.0);
  const std::optional<FilmGrid> grid = FilmGrid::Make(30.0, 24.0);
  ASSERT_EQ(lip.eyes_size(), 2);
  for (int e = 0; e < 2; ++e) {
    const v1::EyeTrack& track = lip.eyes(e);
    const double scale = e == 0 ? 1.0 : 0.97;
    EXPECT_EQ(track.blinks_size(), 2) << track.id();
    EXPECT_EQ(track.open_level(), 1.2 * scale) << track.id();  // E_max, the scale of delta
    const v1::ConvertedCurve* rpc = nullptr;
    for (const v1::ConvertedCurve& c : lip.curves()) {
      if (c.id() == track.id()) rpc = &c;
    }
    ASSERT_NE(rpc, nullptr);
    const v1::RetimedCurve& group = CurveOf(response, track.id());
    const int frames = rpc->values_size();
    ASSERT_EQ(group.values_size(), frames);
    const std::vector<bool> repainted = RepaintedFrames(lip, track.id(), grid, frames);
    // The RPC: the input outside the blinks' repaints, so above the level only on the
    // overshoot's own frames (60-67, the right eye's 61-68), and within the squint at most 0.8.
    int at_level = 0, half_of_squint = 0, group_wide = 0;
    for (int k = 0; k < frames; ++k) {
      const double v = rpc->values(k);
      if (k < 60 || k > 68) {
        EXPECT_LE(v, scale) << track.id() << " frame " << k;
      }
      if (k >= 95 && k <= 139) {
        EXPECT_LE(v, 0.8 * scale) << track.id() << " frame " << k;
      }
      at_level += v == scale;
      half_of_squint += v == 0.5 * (0.8 * scale);
      // The group: LipBlink's values where LipBlink repaints (the blinks, at the squint's
      // level inside it); elsewhere the input held on the group's drawings, so wide only
      // while a drawing of the overshoot is held.
      if (repainted[k]) {
        EXPECT_EQ(group.values(k), v) << track.id() << " frame " << k;
        if (k >= 95 && k <= 139) {
          EXPECT_LE(group.values(k), 0.8 * scale) << track.id() << " frame " << k;
        }
      }
      group_wide += group.values(k) > scale;
    }
    EXPECT_GT(at_level, frames / 2) << track.id();  // before: 1.2 nearly everywhere
    EXPECT_GT(half_of_squint, 0) << track.id();
    EXPECT_GT(group_wide, 0) << track.id();
    EXPECT_LE(group_wide, 16) << track.id();
  }
}

// GROUP_KEEP: the curves come back as they came in (the input at every frame, no steps,
// timing -1), the group has no timing, and a file answer keeps their keyframes untouched.
TEST(CurvesGroupModesTest, KeepGroupIsTheInput) {
  InProcessServer server;
  for (double fps : {30.0, 60.0}) {
    const v1::CurveSet set = GeneratedCurves(fps, 60, 11);
    v1::RetimeCurvesRequest request;
    *request.mutable_curves() = set;
    v1::CurveTimingGroup* hair = request.add_timing_groups();
    hair->set_name("hair");
    hair->add_ids("ParamHair*");
    hair->set_mode(v1::GROUP_KEEP);
    const v1::RetimeCurvesResponse response = Retime(server, request);
    ASSERT_EQ(response.timing_groups_size(), 2);
    const v1::CurveTimingGroupResult& group = response.timing_groups(1);
    EXPECT_EQ(group.timing(), -1);
    EXPECT_EQ(group.frames_per_drawing(), 0);
    EXPECT_EQ(group.key_frames_size(), 0);
    ASSERT_GT(group.curves_size(), 0);
    const CurveSet core = convert::CurveSetFromProto(set, "curves").value();
    for (int c : group.curves()) {
      const v1::RetimedCurve& got = response.curves(c);
      EXPECT_EQ(got.timing(), -1);
      EXPECT_EQ(got.stepped().segments_size(), 0);
      EXPECT_FALSE(got.stepped().has_start());
      EXPECT_EQ(got.hold_histogram_size(), 0);
      EXPECT_EQ(Values(got), SampleEveryFrame(core.curves[c], core.frame_count,
                                              core.beziers_restricted))
          << got.id();
    }
  }
  // The sample as a file: the face kept, its Segments in the answer's file exactly the input's.
  v1::RetimeCurvesRequest file;
  file.set_motion3_json(ReadSample("talk_blink.motion3.json"));
  v1::CurveTimingGroup* face = file.add_timing_groups();
  face->set_name("face");
  face->add_ids("ParamEye*");
  face->add_ids("ParamMouth*");
  face->set_mode(v1::GROUP_KEEP);
  const v1::RetimeCurvesResponse response = Retime(server, file);
  const nlohmann::json in = nlohmann::json::parse(ReadSample("talk_blink.motion3.json"));
  const nlohmann::json out = nlohmann::json::parse(response.motion3_json());
  int kept = 0;
  for (size_t i = 0; i < in["Curves"].size(); ++i) {
    const std::string id = in["Curves"][i]["Id"];
    if (id == "ParamAngleX") {
      EXPECT_NE(out["Curves"][i]["Segments"], in["Curves"][i]["Segments"]);  // stepped
    } else {
      EXPECT_EQ(out["Curves"][i]["Segments"], in["Curves"][i]["Segments"]) << id;
      ++kept;
    }
  }
  EXPECT_EQ(kept, 3);
}

// A group's mode changes only its own curves: the body and hair answer the same bytes whether
// the face is stepped, kept or drawn by LipBlink, and a face in GROUP_STEP is what the face
// group gave before modes existed (its LIP_BLINK answer differs only in the drawn curves).
TEST(CurvesGroupModesTest, GroupsStayIndependentOfEachOthersMode) {
  InProcessServer server;
  for (uint64_t seed : {21u, 22u, 23u}) {
    const v1::CurveSet set = GeneratedCurves(seed == 22 ? 60.0 : 30.0, 70, seed);
    std::map<int, v1::RetimeCurvesResponse> by_mode;
    for (v1::CurveTimingGroupMode mode : {v1::GROUP_STEP, v1::GROUP_KEEP, v1::GROUP_LIP_BLINK}) {
      v1::RetimeCurvesRequest request;
      *request.mutable_curves() = set;
      v1::CurveTimingGroup* face = request.add_timing_groups();
      face->set_name("face");
      for (const char* id : {"ParamEye*", "ParamBrow*", "ParamMouth*", "ParamCheek"}) {
        face->add_ids(id);
      }
      face->set_mode(mode);
      v1::CurveTimingGroup* hair = request.add_timing_groups();
      hair->set_name("hair");
      hair->add_ids("ParamHair*");
      hair->set_frames_per_drawing(2);
      by_mode[mode] = Retime(server, request);
    }
    const v1::RetimeCurvesResponse& step = by_mode[v1::GROUP_STEP];
    const std::set<std::string> face = GroupIds(step, "face");
    const std::set<std::string> drawn = {"ParamMouthOpenY", "ParamEyeLOpen", "ParamEyeROpen"};
    for (int mode : {v1::GROUP_KEEP, v1::GROUP_LIP_BLINK}) {
      const v1::RetimeCurvesResponse& other = by_mode[mode];
      ASSERT_EQ(other.curves_size(), step.curves_size());
      for (int c = 0; c < step.curves_size(); ++c) {
        const std::string& id = step.curves(c).id();
        const bool changes = mode == v1::GROUP_KEEP ? face.count(id) > 0 : drawn.count(id) > 0;
        if (changes) continue;
        EXPECT_EQ(Values(other.curves(c)), Values(step.curves(c))) << id << " mode " << mode;
        EXPECT_EQ(other.curves(c).stepped().SerializeAsString(),
                  step.curves(c).stepped().SerializeAsString())
            << id;
      }
    }
    // The default grouping is this request's LIP_BLINK face (hair on threes aside).
    v1::RetimeCurvesRequest defaults;
    *defaults.mutable_curves() = set;
    const v1::RetimeCurvesResponse by_default = Retime(server, defaults);
    for (const std::string& id : drawn) {
      EXPECT_EQ(Values(CurveOf(by_default, id)), Values(CurveOf(by_mode[v1::GROUP_LIP_BLINK], id)))
          << id;
    }
  }
}

// Bad mode fields, each named with its path.
TEST(CurvesGroupModesTest, BadModeFieldsAreNamed) {
  InProcessServer server;
  const v1::CurveSet set = SampleCurves("talk_blink.motion3.json");
  struct Case {
    std::function<void(v1::CurveTimingGroup*)> change;
    std::string message;
  };
  const std::vector<Case> cases = {
      {[](v1::CurveTimingGroup* g) { g->set_mode(static_cast<v1::CurveTimingGroupMode>(7)); },
       "timing_groups[0].mode: 7 is not a CurveTimingGroupMode"},
      {[](v1::CurveTimingGroup* g) { g->mutable_mouth()->set_mid_ratio(0.3); },
       "timing_groups[0]: mouth, eyes and seed are for mode GROUP_LIP_BLINK, and the mode is "
       "CURVE_TIMING_GROUP_MODE_UNSPECIFIED"},
      {[](v1::CurveTimingGroup* g) {
         g->set_mode(v1::GROUP_KEEP);
         g->set_seed(3);
       },
       "timing_groups[0]: mouth, eyes and seed are for mode GROUP_LIP_BLINK, and the mode is "
       "GROUP_KEEP"},
      {[](v1::CurveTimingGroup* g) {
         g->set_mode(v1::GROUP_LIP_BLINK);
         g->mutable_mouth()->add_ids("ParamAngleX");  // a curve of another group
       },
       "timing_groups[0].mouth.ids[0]: \"ParamAngleX\" is not a curve of timing group \"face\""},
      {[](v1::CurveTimingGroup* g) {
         g->set_mode(v1::GROUP_LIP_BLINK);
         g->mutable_eyes()->set_mid_ratio(1.5);
       },
       "timing_groups[0].eyes.mid_ratio"},
  };
  for (const Case& c : cases) {
    v1::RetimeCurvesRequest request;
    *request.mutable_curves() = set;
    v1::CurveTimingGroup* g = request.add_timing_groups();
    g->set_name("face");
    g->add_ids("ParamEye*");
    g->add_ids("ParamMouth*");
    c.change(g);
    v1::RetimeCurvesResponse response;
    const grpc::Status status = CallRpc(server.stub(), request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << c.message;
    EXPECT_THAT(status.error_message(), ::testing::StartsWith(c.message));
  }
}

}  // namespace
}  // namespace koma::server
