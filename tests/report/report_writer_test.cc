// The report writers on hand-made requests and responses: the page carries the response's
// data unchanged, the same call gives the same bytes, text from files cannot break out of the
// page, and the shared encoders (plot thinning, packed positions, base64) are exact.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "client/report/curves_report.h"
#include "client/report/lip_blink_report.h"
#include "client/report/lip_blink_voice_report.h"
#include "client/report/report_data.h"
#include "client/report/skeletal_report.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace koma::client::report {
namespace {

using ::testing::ElementsAre;
using ::testing::ElementsAreArray;
using ::testing::HasSubstr;
using ::testing::Not;

// The JSON the page carries in <script type="application/json" id="koma-data">.
nlohmann::json PageData(const std::string& page) {
  const std::string open = "id=\"koma-data\">";
  const size_t begin = page.find(open);
  EXPECT_NE(begin, std::string::npos);
  const size_t end = page.find("</script>", begin);
  return nlohmann::json::parse(page.substr(begin + open.size(), end - begin - open.size()));
}

// Naive reading of PackQuantised: base64, varints, zigzag, running sums per value of a frame.
std::vector<double> Unpack(const std::string& base64, int per_frame, double step) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes;
  uint32_t bits = 0;
  int count = 0;
  for (char c : base64) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<uint32_t>(alphabet.find(c));
    count += 6;
    if (count >= 8) {
      count -= 8;
      bytes.push_back(static_cast<char>((bits >> count) & 0xff));
    }
  }
  std::vector<double> values;
  std::vector<int64_t> sums(per_frame, 0);
  size_t pos = 0;
  while (pos < bytes.size()) {
    uint64_t v = 0;
    int shift = 0;
    uint8_t b;
    do {
      b = static_cast<uint8_t>(bytes[pos++]);
      v |= static_cast<uint64_t>(b & 0x7f) << shift;
      shift += 7;
    } while (b & 0x80);
    const int64_t delta =
        (v & 1) ? -static_cast<int64_t>(v >> 1) - 1 : static_cast<int64_t>(v >> 1);
    int64_t& sum = sums[values.size() % per_frame];
    sum += delta;
    values.push_back(static_cast<double>(sum) * step);
  }
  return values;
}

// Two joints in the positions form: the root and a hand 10 units above it, moving along x.
v1::RetimeSkeletalRequest PositionsRequest(int frames) {
  v1::RetimeSkeletalRequest request;
  v1::SkeletalMotion* motion = request.mutable_motion();
  v1::Joint* root = motion->mutable_skeleton()->add_joints();
  root->set_name("Hips");
  root->set_parent(-1);
  v1::Joint* hand = motion->mutable_skeleton()->add_joints();
  hand->set_name("Hand");
  hand->set_parent(0);
  motion->set_frame_time(1.0 / 24);
  motion->set_frame_count(frames);
  for (int f = 0; f < frames; ++f) {
    for (double v : {0.5 * f, 0.0, 0.0, 0.5 * f + std::sin(f), 10.0, std::cos(f)}) {
      motion->mutable_positions()->add_values(v);
    }
  }
  return request;
}

v1::RetimeSkeletalResponse SkeletalResponse() {
  v1::RetimeSkeletalResponse r;
  for (int s : {0, 0, 2, 2, 2, 5}) r.add_source_frames(s);
  for (v1::FrameKind k :
       {v1::ORIGINAL, v1::DUPLICATE, v1::ORIGINAL, v1::HELD, v1::HELD, v1::ORIGINAL}) {
    r.add_kinds(k);
  }
  r.add_deleted_frames(1);
  r.add_hidden_frames(3);
  r.add_hidden_frames(4);
  for (double s : {0.0, 1.5, 2.25, 0.125, 7.0, 3.0}) r.add_input_ssd(s);
  r.set_omissions_applied(1);
  r.set_duplicates_applied(1);
  r.set_holds_applied(2);
  r.set_omissions_requested(1);
  r.set_holds_requested(2);
  r.set_max_hold(3);
  return r;
}

TEST(SkeletalReport, CarriesTheResponse) {
  const v1::RetimeSkeletalRequest request = PositionsRequest(6);
  const v1::RetimeSkeletalResponse response = SkeletalResponse();
  const nlohmann::json data =
      PageData(RenderReport(SkeletalReportWriter(request, response, "clip.bvh")));
  EXPECT_THAT(data["source_frames"].get<std::vector<int>>(), ElementsAre(0, 0, 2, 2, 2, 5));
  EXPECT_EQ(data["kinds"], "ODOHHO");
  EXPECT_THAT(data["deleted"].get<std::vector<int>>(), ElementsAre(1));
  EXPECT_THAT(data["hidden"].get<std::vector<int>>(), ElementsAre(3, 4));
  EXPECT_THAT(data["ssd"]["y"].get<std::vector<double>>(),
              ElementsAre(0.0, 1.5, 2.25, 0.125, 7.0, 3.0));
  EXPECT_DOUBLE_EQ(data["ssd"]["x"][2].get<double>(), Round6(2.0 / 24));  // seconds
  EXPECT_EQ(data["frames_in"], 6);
  EXPECT_EQ(data["timing_fps"], 0.0);
  EXPECT_THAT(data["joints"]["parents"].get<std::vector<int>>(), ElementsAre(-1, 0));
  EXPECT_EQ(data["header"]["input"], "clip.bvh");
  EXPECT_EQ(data["header"]["rpc"], "RetimeSkeletal");
}

TEST(SkeletalReport, PlayerPositionsAreTheInputsWithinHalfAStep) {
  const v1::RetimeSkeletalRequest request = PositionsRequest(50);
  const nlohmann::json data =
      PageData(RenderReport(SkeletalReportWriter(request, SkeletalResponse(), "clip.bvh")));
  const nlohmann::json& pose = data["pose"];
  ASSERT_EQ(pose["dims"], 3);
  const double step = pose["step"].get<double>();
  // The body: the hand is up to 10 units from the root, so a step is 20 / 1024 units.
  EXPECT_NEAR(step, 20.0 / 1024, 1e-6);
  const std::vector<double> got = Unpack(pose["data"].get<std::string>(), 6, step);
  const auto& want = request.motion().positions().values();
  ASSERT_EQ(got.size(), static_cast<size_t>(want.size()));
  for (int i = 0; i < want.size(); ++i) EXPECT_NEAR(got[i], want[i], step / 2 + 1e-12) << i;
}

TEST(SkeletalReport, ChannelFormRunsForwardKinematics) {
  v1::RetimeSkeletalRequest request;
  v1::SkeletalMotion* motion = request.mutable_motion();
  v1::Joint* root = motion->mutable_skeleton()->add_joints();
  root->set_name("Hips");
  root->set_parent(-1);
  for (const char* c : {"Xposition", "Yposition", "Zposition"}) root->add_channels(c);
  v1::Joint* head = motion->mutable_skeleton()->add_joints();
  head->set_name("Head");
  head->set_parent(0);
  head->mutable_offset()->set_y(4);
  motion->set_frame_time(1.0 / 30);
  motion->set_frame_count(3);
  for (double v : {0.0, 0.0, 0.0, 1.0, 2.0, 3.0, -1.0, 0.5, 2.0}) {
    motion->mutable_channels()->add_values(v);
  }
  const nlohmann::json pose =
      PageData(RenderReport(SkeletalReportWriter(request, SkeletalResponse(), "c.bvh")))["pose"];
  const double step = pose["step"].get<double>();
  const std::vector<double> got = Unpack(pose["data"].get<std::string>(), 6, step);
  const std::vector<double> want = {0, 0, 0, 0, 4, 0, 1, 2, 3, 1, 6, 3, -1, 0.5, 2, -1, 4.5, 2};
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(got[i], want[i], step / 2 + 1e-12) << i;
}

TEST(SkeletalReport, CameraGivesTwoDimensions) {
  v1::RetimeSkeletalRequest request = PositionsRequest(4);
  // Orthographic camera scaling x by 0.1 and y by 0.2 (column-major identity otherwise).
  const double m[16] = {0.1, 0, 0, 0, 0, 0.2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  for (double v : m) request.add_camera(v);
  const nlohmann::json pose =
      PageData(RenderReport(SkeletalReportWriter(request, SkeletalResponse(), "c.bvh")))["pose"];
  EXPECT_EQ(pose["dims"], 2);
  EXPECT_EQ(pose["camera"], true);
  const double step = pose["step"].get<double>();
  const std::vector<double> got = Unpack(pose["data"].get<std::string>(), 4, step);
  ASSERT_EQ(got.size(), 16u);
  const auto& p = request.motion().positions().values();
  for (int f = 0; f < 4; ++f) {
    for (int j = 0; j < 2; ++j) {
      EXPECT_NEAR(got[f * 4 + j * 2], 0.1 * p[f * 6 + j * 3], step / 2 + 1e-12);
      EXPECT_NEAR(got[f * 4 + j * 2 + 1], 0.2 * p[f * 6 + j * 3 + 1], step / 2 + 1e-12);
    }
  }
}

TEST(SkeletalReport, FilmGridArrays) {
  v1::RetimeSkeletalRequest request = PositionsRequest(10);
  request.mutable_motion()->set_frame_time(1.0 / 48);
  v1::RetimeSkeletalResponse response = SkeletalResponse();
  response.set_timing_fps(24);
  for (int g : {0, 0, 1, 1, 2, 2}) response.add_grid_frames(g);
  for (int s : {0, 2, 4}) response.add_grid_source_frames(s);
  const nlohmann::json data =
      PageData(RenderReport(SkeletalReportWriter(request, response, "c.bvh")));
  EXPECT_THAT(data["grid_frames"].get<std::vector<int>>(), ElementsAre(0, 0, 1, 1, 2, 2));
  EXPECT_THAT(data["grid_source_frames"].get<std::vector<int>>(), ElementsAre(0, 2, 4));
  EXPECT_EQ(data["timing_fps"], 24.0);
  // input_ssd is per grid frame: x in seconds of the grid.
  EXPECT_DOUBLE_EQ(data["ssd"]["x"][1].get<double>(), Round6(1.0 / 24));
}

TEST(Report, SameCallSameBytes) {
  const v1::RetimeSkeletalRequest request = PositionsRequest(30);
  const v1::RetimeSkeletalResponse response = SkeletalResponse();
  const std::string first = RenderReport(SkeletalReportWriter(request, response, "a.bvh"));
  // A copy through the wire format: equal messages, other objects and addresses.
  v1::RetimeSkeletalRequest request2;
  ASSERT_TRUE(request2.ParseFromString(request.SerializeAsString()));
  v1::RetimeSkeletalResponse response2;
  ASSERT_TRUE(response2.ParseFromString(response.SerializeAsString()));
  EXPECT_EQ(first, RenderReport(SkeletalReportWriter(request2, response2, "a.bvh")));
  // And a different response gives a different page.
  response2.set_source_frames(1, 1);
  EXPECT_NE(first, RenderReport(SkeletalReportWriter(request2, response2, "a.bvh")));
}

TEST(Report, FileNamesCannotBreakOutOfThePage) {
  const std::string name = "</script><script>alert(1)</script>&<b>.bvh";
  const std::string page =
      RenderReport(SkeletalReportWriter(PositionsRequest(4), SkeletalResponse(), name));
  EXPECT_THAT(page, Not(HasSubstr("<script>alert(1)")));
  EXPECT_THAT(page, HasSubstr("<title>koma skeletal: &lt;/script&gt;&lt;script&gt;"));
  EXPECT_EQ(PageData(page)["header"]["input"], name);
  // Every template marker was filled.
  for (const char* marker :
       {"{{TITLE}}", "{{KIND}}", "{{STYLE}}", "{{DATA}}", "{{COMMON_SCRIPT}}", "{{KIND_SCRIPT}}"}) {
    EXPECT_THAT(page, Not(HasSubstr(marker)));
  }
  EXPECT_THAT(page, HasSubstr("<body data-kind=\"skeletal\""));
  EXPECT_THAT(page, HasSubstr("function skeletalReport"));
}

// The header names the input's format as the format table has it: sniffed from the file when
// it is there (a Spine skeleton and a motion3.json are both .json), else by its name.
TEST(Report, HeaderNamesTheInputFormatFromTheFormatTable) {
  const auto format = [](const std::string& input) {
    const nlohmann::json header = PageData(RenderReport(
        SkeletalReportWriter(PositionsRequest(4), SkeletalResponse(), input)))["header"];
    return header.contains("format") ? header["format"].get<std::string>() : "(none)";
  };
  EXPECT_EQ(format(std::string(KOMA_SAMPLES_DIR) + "/pitch.bvh"), "BVH");
  EXPECT_EQ(format(std::string(KOMA_SAMPLES_DIR) + "/wave.glb"), "glTF");
  EXPECT_EQ(format(std::string(KOMA_TESTDATA_DIR) + "/fbx/assimp_huesitos.fbx"), "FBX");
  EXPECT_EQ(format(std::string(KOMA_TESTDATA_DIR) + "/spine/hero-4.1.json"), "Spine JSON");
  EXPECT_EQ(format("not/there/clip.bvh"), "BVH");  // by its name
  EXPECT_EQ(format("not/there/voice.FLAC"), "audio");
  EXPECT_EQ(format("-"), "(none)");
  EXPECT_EQ(format("notes.txt"), "(none)");
}

TEST(Report, StandardInputIsNamed) {
  const nlohmann::json data =
      PageData(RenderReport(SkeletalReportWriter(PositionsRequest(4), SkeletalResponse(), "-")));
  EXPECT_EQ(data["header"]["input"], "standard input");
}

TEST(CurvesReport, CarriesTheResponse) {
  v1::RetimeCurvesRequest request;
  v1::CurveSet* set = request.mutable_curves();
  set->set_fps(30);
  set->set_frame_count(7);
  v1::Curve* curve = set->add_curves();
  curve->set_id("ParamAngleX");
  curve->mutable_start()->set_value(0);
  v1::CurveSegment* segment = curve->add_segments();
  segment->set_type(v1::SEGMENT_LINEAR);
  segment->mutable_end()->set_frame(6);
  segment->mutable_end()->set_value(12);
  v1::RetimeCurvesResponse response;
  response.add_key_frames(0);
  response.add_key_frames(6);
  v1::DrawingTiming* timing = response.add_timings();
  timing->set_frames_per_drawing(3);
  for (int d : {0, 0, 0, 1, 1, 1, 2}) timing->add_drawing_of_frame(d);
  for (int s : {0, 3, 6}) timing->add_drawing_start(s);
  v1::RetimedCurve* out = response.add_curves();
  out->set_id("ParamAngleX");
  for (double v : {0, 0, 0, 6, 6, 6, 12}) out->add_values(v);
  out->mutable_stepped()->mutable_start()->set_value(0);
  for (auto [frame, value] : {std::pair{3.0, 6.0}, {6.0, 12.0}}) {
    v1::CurveSegment* s = out->mutable_stepped()->add_segments();
    s->set_type(v1::SEGMENT_STEPPED);
    s->mutable_end()->set_frame(frame);
    s->mutable_end()->set_value(value);
  }
  v1::HoldCount* hold = out->add_hold_histogram();
  hold->set_length(3);
  hold->set_drawings(2);
  const nlohmann::json data =
      PageData(RenderReport(CurvesReportWriter(request, response, "a.motion3.json")));
  EXPECT_THAT(data["key_frames"].get<std::vector<int>>(), ElementsAre(0, 6));
  EXPECT_THAT(data["timings"][0]["drawing_of_frame"].get<std::vector<int>>(),
              ElementsAre(0, 0, 0, 1, 1, 1, 2));
  EXPECT_THAT(data["timings"][0]["drawing_start"].get<std::vector<int>>(), ElementsAre(0, 3, 6));
  const nlohmann::json& c = data["curves"][0];
  EXPECT_EQ(c["id"], "ParamAngleX");
  // Before: the linear input at every frame; after: the stepped keys, in seconds.
  EXPECT_THAT(c["before"]["y"].get<std::vector<double>>(), ElementsAre(0, 2, 4, 6, 8, 10, 12));
  EXPECT_THAT(c["after"]["x"].get<std::vector<double>>(), ElementsAre(0, 0.1, 0.2));
  EXPECT_THAT(c["after"]["y"].get<std::vector<double>>(), ElementsAre(0, 6, 12));
  EXPECT_EQ(c["histogram"], nlohmann::json::parse("[[3, 2]]"));
  EXPECT_EQ(data["grid_count"], 0);
}

TEST(LipBlinkReport, CarriesTheResponse) {
  v1::LipBlinkRequest request;
  v1::CurveSet* set = request.mutable_curves();
  set->set_fps(30);
  set->set_frame_count(4);
  v1::Curve* mouth = set->add_curves();
  mouth->set_id("ParamMouthOpenY");
  for (double v : {0.0, 0.5, 1.0, 0.0}) mouth->add_samples(v);
  v1::LipBlinkResponse response;
  response.set_timing_fps(24);
  v1::MouthTrack* track = response.add_mouths();
  track->set_id("ParamMouthOpenY");
  v1::FrameInterval* speech = track->add_speech();
  speech->set_begin(1);
  speech->set_end(3);
  v1::MouthHold* hold = track->add_holds();
  hold->set_begin(1);
  hold->set_length(2);
  hold->set_shape(v1::MOUTH_OPEN);
  v1::EyeTrack* eye = response.add_eyes();
  eye->set_id("ParamEyeLOpen");
  v1::Blink* blink = eye->add_blinks();
  blink->set_closed_begin(2);
  blink->set_closed_end(2);
  blink->set_hold(1);
  blink->set_automatic(true);
  v1::ConvertedCurve* converted = response.add_curves();
  converted->set_id("ParamMouthOpenY");
  for (double v : {0.0, 1.0, 1.0, 0.0}) converted->add_values(v);
  const nlohmann::json data =
      PageData(RenderReport(LipBlinkReportWriter(request, response, "t.motion3.json")));
  EXPECT_EQ(data["mouths"][0]["speech"], nlohmann::json::parse("[[1, 3]]"));
  EXPECT_EQ(data["mouths"][0]["holds"], nlohmann::json::parse("[[1, 2, \"open\"]]"));
  EXPECT_EQ(data["eyes"][0]["blinks"][0]["closed_begin"], 2);
  EXPECT_EQ(data["eyes"][0]["blinks"][0]["automatic"], true);
  EXPECT_EQ(data["unit_fps"], 24.0);
  EXPECT_THAT(data["curves"][0]["before"]["y"].get<std::vector<double>>(),
              ElementsAre(0, 0.5, 1, 0));
  EXPECT_THAT(data["curves"][0]["after"]["y"].get<std::vector<double>>(), ElementsAre(0, 1, 1, 0));
  // The face player's every frame.
  EXPECT_THAT(data["curves"][0]["frames_before"].get<std::vector<double>>(),
              ElementsAre(0, 0.5, 1, 0));
  EXPECT_THAT(data["curves"][0]["frames_after"].get<std::vector<double>>(),
              ElementsAre(0, 1, 1, 0));
}

// Naive base64 decoding (RFC 4648, padded).
std::string Unbase64(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes;
  uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<uint32_t>(alphabet.find(c));
    count += 6;
    if (count >= 8) {
      count -= 8;
      bytes.push_back(static_cast<char>((bits >> count) & 0xff));
    }
  }
  return bytes;
}

// A voice call as the CLI makes it: a recording, a new motion of 5 frames at 30 fps, and what
// the server answered on the 24 fps grid (loudness of 4 grid frames, one speech interval).
struct VoiceCall {
  v1::LipBlinkRequest request;
  v1::LipBlinkResponse response;
  VoiceReportSources sources;
};

VoiceCall MakeVoiceCall(const std::string& audio) {
  VoiceCall call;
  call.request.set_audio(audio);
  call.request.set_voice_motion_fps(30);
  call.request.mutable_voice_settings()->set_start_above_floor_db(12);
  v1::LipBlinkResponse& r = call.response;
  r.set_timing_fps(24);
  v1::LipBlinkVoiceAnalysis* v = r.mutable_voice();
  v->set_sample_rate(16000);
  v->set_channels(2);
  v->set_duration_s(0.16);
  v->set_frame_fps(24);
  for (double db : {-150.0, -61.25, -20.5, -33.125}) v->add_loudness_dbfs(db);
  v->set_noise_floor_dbfs(-61.25);
  v->set_start_dbfs(-49.25);
  v->set_stay_dbfs(-55.0);
  v->set_loud_dbfs(-20.5);
  v1::FrameInterval* speech = v->add_speech();
  speech->set_begin(2);
  speech->set_end(4);
  v1::MouthTrack* track = r.add_mouths();
  track->set_id("ParamMouthOpenY");
  *track->add_speech() = *speech;
  v1::MouthHold* hold = track->add_holds();
  hold->set_begin(2);
  hold->set_length(2);
  hold->set_shape(v1::MOUTH_MID);
  track->set_open_level(1);
  track->set_mid_level(0.5);
  v1::ConvertedCurve* curve = r.add_curves();
  curve->set_id("ParamMouthOpenY");
  for (double value : {0.0, 0.0, 0.5, 0.5, 0.5}) curve->add_values(value);
  call.sources.voice_name = "voice.wav";
  call.sources.motion_fps = 30;
  call.sources.audio = call.request.audio();
  call.sources.audio_link = "voice.wav";
  return call;
}

TEST(LipBlinkVoiceReport, CarriesTheAnalysisAndEmbedsTheRecording) {
  std::string audio("RIFF\x24\x00\x00\x00WAVEfmt \x10\x00\x00\x00", 20);
  for (int i = 0; i < 300; ++i) audio.push_back(static_cast<char>(i * 7));  // every byte value
  const VoiceCall call = MakeVoiceCall(audio);
  const std::string page =
      RenderReport(LipBlinkVoiceReportWriter(call.request, call.response, call.sources));
  EXPECT_THAT(page, HasSubstr("<body data-kind=\"lipblink_voice\""));
  EXPECT_THAT(page, HasSubstr("function lipBlinkVoiceReport(D)"));  // templates/lipblink_voice.js
  const nlohmann::json data = PageData(page);
  const nlohmann::json& v = data["voice"];
  EXPECT_EQ(v["kind"], "audio");
  EXPECT_EQ(v["frame_fps"], 24.0);
  EXPECT_EQ(v["frames"], 4);
  EXPECT_THAT(v["loudness"]["y"].get<std::vector<double>>(),
              ElementsAre(-150, -61.25, -20.5, -33.125));
  EXPECT_THAT(v["loudness"]["x"].get<std::vector<double>>(),
              ElementsAre(0, Round6(1.0 / 24), Round6(2.0 / 24), Round6(3.0 / 24)));
  EXPECT_EQ(v["noise_floor_dbfs"], -61.25);
  EXPECT_EQ(v["start_dbfs"], -49.25);
  EXPECT_EQ(v["stay_dbfs"], -55.0);
  EXPECT_EQ(v["loud_dbfs"], -20.5);
  EXPECT_EQ(v["speech"], nlohmann::json::parse("[[2, 4]]"));
  EXPECT_EQ(data["mouths"][0]["holds"], nlohmann::json::parse("[[2, 2, \"mid\"]]"));
  EXPECT_THAT(data["curves"][0]["frames_after"].get<std::vector<double>>(),
              ElementsAre(0, 0, 0.5, 0.5, 0.5));
  EXPECT_EQ(data["fps"], 30.0);
  EXPECT_EQ(data["frames"], 5);
  EXPECT_EQ(data["unit_fps"], 24.0);
  // The recording, byte for byte, as a data: URL the page's <audio> plays.
  const nlohmann::json& a = data["audio"];
  EXPECT_EQ(a["embedded"], true);
  EXPECT_EQ(a["mime"], "audio/wav");
  EXPECT_EQ(a["bytes"], static_cast<int64_t>(audio.size()));
  const std::string src = a["src"];
  const std::string prefix = "data:audio/wav;base64,";
  ASSERT_EQ(src.substr(0, prefix.size()), prefix);
  EXPECT_EQ(Unbase64(src.substr(prefix.size())), audio);
  // The header: the recording named, the request's setting given, the server's marked default.
  EXPECT_EQ(data["header"]["input"], "voice.wav");
  EXPECT_THAT(data["header"]["options"].dump(),
              HasSubstr("[\"speech starts above floor\",\"12 dB\"]"));
  EXPECT_THAT(data["header"]["counts"].dump(),
              HasSubstr("[\"speech thresholds\",\"start -49.2, stay -55.0 dBFS\"]"));
  EXPECT_THAT(data["header"]["options"].dump(), HasSubstr("\"shortest speech\",\"2 frames (default)\""));
  // Same call, same bytes.
  EXPECT_EQ(page, RenderReport(LipBlinkVoiceReportWriter(call.request, call.response, call.sources)));
}

TEST(LipBlinkVoiceReport, LinksARecordingOverTheLimit) {
  VoiceCall call = MakeVoiceCall(std::string("fLaC") + std::string(100, 'x'));
  call.sources.audio_max_bytes = 103;
  call.sources.audio_link = "../sound/voice%20take%202.flac";
  const std::string page =
      RenderReport(LipBlinkVoiceReportWriter(call.request, call.response, call.sources));
  const nlohmann::json data = PageData(page);
  EXPECT_EQ(data["audio"]["embedded"], false);
  EXPECT_EQ(data["audio"]["mime"], "audio/flac");
  EXPECT_EQ(data["audio"]["src"], "../sound/voice%20take%202.flac");
  EXPECT_THAT(page, Not(HasSubstr("data:audio")));
  // At the limit it is embedded.
  call.sources.audio_max_bytes = 104;
  EXPECT_EQ(PageData(RenderReport(LipBlinkVoiceReportWriter(call.request, call.response,
                                                            call.sources)))["audio"]["embedded"],
            true);
}

TEST(LipBlinkVoiceReport, RhubarbCuesHaveNoRecording) {
  VoiceCall call = MakeVoiceCall("");
  call.request.set_rhubarb_cues("0.00\tX\n0.10\tD\n");
  call.response.mutable_voice()->clear_loudness_dbfs();
  call.sources.audio = {};
  const nlohmann::json data =
      PageData(RenderReport(LipBlinkVoiceReportWriter(call.request, call.response, call.sources)));
  EXPECT_TRUE(data["audio"].is_null());
  EXPECT_EQ(data["voice"]["kind"], "rhubarb");
  EXPECT_EQ(data["voice"]["frames"], 0);
  EXPECT_THAT(data["header"]["options"].dump(), HasSubstr("[\"mouth mode\",\"follow\"]"));
}

TEST(LipBlinkVoiceReport, AnswerWithoutCurvesIsRefusedNamingThePath) {
  const std::string path = ::testing::TempDir() + "/never_written_voice.html";
  VoiceCall call = MakeVoiceCall("RIFF");
  call.response.clear_curves();
  const absl::Status s = WriteLipBlinkVoiceReport(path, call.request, call.response, call.sources);
  EXPECT_FALSE(s.ok());
  EXPECT_THAT(std::string(s.message()), HasSubstr(path));
  EXPECT_EQ(std::fopen(path.c_str(), "r"), nullptr);
}

TEST(AudioMimeType, FromTheFirstBytes) {
  EXPECT_EQ(AudioMimeType("RIFF....WAVE"), "audio/wav");
  EXPECT_EQ(AudioMimeType("RF64....WAVE"), "audio/wav");
  EXPECT_EQ(AudioMimeType("fLaC\0\0\0\x22"), "audio/flac");
  EXPECT_EQ(AudioMimeType("OggS\0\x02"), "audio/ogg");
  EXPECT_EQ(AudioMimeType("ID3\x04\0"), "audio/mpeg");
  EXPECT_EQ(AudioMimeType("\xFF\xFB\x90\x64"), "audio/mpeg");
  EXPECT_EQ(AudioMimeType("FORM....AIFF"), "audio/aiff");
  EXPECT_EQ(AudioMimeType("hello"), "application/octet-stream");
  EXPECT_EQ(AudioMimeType(""), "application/octet-stream");
}

TEST(AudioLink, RelativeToThePageAndPercentEncoded) {
  EXPECT_EQ(AudioLink("/a/b/voice.wav", "/a/out/r.html"), "../b/voice.wav");
  EXPECT_EQ(AudioLink("/a/voice.wav", "/a/r.html"), "voice.wav");
  EXPECT_EQ(AudioLink("/a/my take#1?.wav", "/a/r.html"), "my%20take%231%3F.wav");
  EXPECT_EQ(AudioLink("/a/x/../voice.wav", "/a/r.html"), "voice.wav");
  EXPECT_EQ(AudioLink("/a/b/voice.wav", "-"), "file:///a/b/voice.wav");
}

TEST(Report, RequestsWithoutParsedDataAreRefusedNamingThePath) {
  const std::string path = ::testing::TempDir() + "/never_written.html";
  v1::RetimeSkeletalRequest skeletal;
  skeletal.set_bvh_text("HIERARCHY ...");
  absl::Status s = WriteSkeletalReport(path, skeletal, SkeletalResponse(), "a.bvh");
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), HasSubstr(path));
  EXPECT_EQ(
      WriteCurvesReport(path, v1::RetimeCurvesRequest(), v1::RetimeCurvesResponse(), "a").code(),
      absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(WriteLipBlinkReport(path, v1::LipBlinkRequest(), v1::LipBlinkResponse(), "a").code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(std::fopen(path.c_str(), "r"), nullptr);
}

TEST(Report, WritesTheFileWhole) {
  const std::string path = ::testing::TempDir() + "/report_writer_test.html";
  const v1::RetimeSkeletalRequest request = PositionsRequest(8);
  ASSERT_TRUE(WriteSkeletalReport(path, request, SkeletalResponse(), "a.bvh").ok());
  std::FILE* file = std::fopen(path.c_str(), "rb");
  ASSERT_NE(file, nullptr);
  std::string text;
  char buffer[4096];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, file)) > 0) text.append(buffer, n);
  std::fclose(file);
  std::remove(path.c_str());
  EXPECT_EQ(text, RenderReport(SkeletalReportWriter(request, SkeletalResponse(), "a.bvh")));
  // A folder that does not exist: an error naming the path, no file.
  const absl::Status missing =
      WriteSkeletalReport("/nonexistent-dir/r.html", request, SkeletalResponse(), "a.bvh");
  EXPECT_FALSE(missing.ok());
  EXPECT_THAT(std::string(missing.message()), HasSubstr("/nonexistent-dir/r.html"));
}

TEST(ThinnedPlot, KeepsEveryPeakWithinTheLimit) {
  std::vector<double> values(100000);
  for (size_t i = 0; i < values.size(); ++i) values[i] = std::sin(i * 0.001);
  values[77777] = 50;  // a spike one sample wide
  values[12345] = -50;
  const nlohmann::json plot = ThinnedPlot(values, 0.5);
  const std::vector<double> x = plot["x"].get<std::vector<double>>();
  const std::vector<double> y = plot["y"].get<std::vector<double>>();
  EXPECT_LE(y.size(), static_cast<size_t>(kMaxPlotPoints));
  EXPECT_GE(y.size(), static_cast<size_t>(kMaxPlotPoints) * 9 / 10);
  EXPECT_TRUE(std::is_sorted(x.begin(), x.end()));
  EXPECT_THAT(y, ::testing::Contains(50.0));
  EXPECT_THAT(y, ::testing::Contains(-50.0));
  EXPECT_THAT(x, ::testing::Contains(77777 * 0.5));
  // Short series are kept whole.
  EXPECT_EQ(ThinnedPlot(std::vector<double>{1, 2, 3}, 1)["y"].size(), 3u);
}

TEST(PackQuantised, RoundTripsLargeAndNegativeJumps) {
  const std::vector<double> values = {0, 1e6, -1e6, 3, 3, -2.5e9, 7, 0.24, -0.26, 1e15};
  const double step = 0.5;
  const std::vector<double> got = Unpack(PackQuantised(values, 2, step), 2, step);
  ASSERT_EQ(got.size(), values.size());
  for (size_t i = 0; i < values.size(); ++i) EXPECT_NEAR(got[i], values[i], step / 2) << i;
}

TEST(Base64, Rfc4648Vectors) {
  EXPECT_EQ(Base64(""), "");
  EXPECT_EQ(Base64("f"), "Zg==");
  EXPECT_EQ(Base64("fo"), "Zm8=");
  EXPECT_EQ(Base64("foo"), "Zm9v");
  EXPECT_EQ(Base64("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64(std::string("\xff\x00\x80", 3)), "/wCA");
}

}  // namespace
}  // namespace koma::client::report
