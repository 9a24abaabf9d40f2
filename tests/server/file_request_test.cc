// Files over the wire (server/file_requests.h): a request carrying a BVH, motion3.json or CSV
// file answers what the decoded request answers, plus the retimed file, byte for byte the one
// the `koma` CLI writes from the decoded answer (the CLI's steps are redone here with the
// same convert/ and formats/ functions it calls). Every sample and real mocap file, several
// option sets; limits on files; the raw service's bytes against the message path.
#include <gtest/gtest.h>
#include <prometheus/registry.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "convert/curve_text.h"
#include "convert/curves_convert.h"
#include "convert/skeletal_convert.h"
#include "formats/bvh.h"
#include "server/curves_request.h"
#include "server/lip_blink_request.h"
#include "server/skeletal_request.h"
#include "tests/server/in_process_server.h"
#include "tests/testing/status_matchers.h"

namespace koma::testing {
namespace {

std::string ReadTestFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << path;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The samples and the real mocap files.
const std::vector<std::string>& BvhFiles() {
  static const std::vector<std::string> files = {
      KOMA_SAMPLES_DIR "/pitch.bvh", KOMA_SAMPLES_DIR "/mocap_120fps.bvh",
      KOMA_TESTDATA_DIR "/bvh_test1.bvh", KOMA_TESTDATA_DIR "/bvh_test2.bvh",
      KOMA_TESTDATA_DIR "/bvh_test3.bvh"};
  return files;
}

// Option sets for RetimeSkeletal: the defaults (24 fps grid), no grid, the grid at its own
// rate, and explicit counts in the other step order. The 2- and 3-frame edge-case files
// (CRLF, unusual channels) are too short for a grid or omissions: only the no-grid set.
std::vector<v1::RetimeSkeletalRequest> SkeletalOptionSets(const std::string& path) {
  if (path.find("two_joints_crlf") != std::string::npos ||
      path.find("unusual_channels") != std::string::npos) {
    std::vector<v1::RetimeSkeletalRequest> sets(1);
    sets[0].set_timing_fps(0);
    return sets;
  }
  std::vector<v1::RetimeSkeletalRequest> sets(4);
  sets[1].set_timing_fps(0);
  sets[2].set_output_rate(v1::TIMING_RATE);
  sets[3].set_timing_fps(0);
  sets[3].set_omissions(2);
  sets[3].set_holds(5);
  sets[3].set_max_hold(2);
  sets[3].set_order(v1::HOLD_THEN_OMIT);
  sets[3].set_root_relative(true);
  return sets;
}

grpc::Status Call(InProcessServer& server, const v1::RetimeSkeletalRequest& request,
                  v1::RetimeSkeletalResponse* response) {
  grpc::ClientContext context;
  SetTestDeadline(context);
  return server.stub().RetimeSkeletal(&context, request, response);
}
grpc::Status Call(InProcessServer& server, const v1::RetimeCurvesRequest& request,
                  v1::RetimeCurvesResponse* response) {
  grpc::ClientContext context;
  SetTestDeadline(context);
  return server.stub().RetimeCurves(&context, request, response);
}
grpc::Status Call(InProcessServer& server, const v1::LipBlinkRequest& request,
                  v1::LipBlinkResponse* response) {
  grpc::ClientContext context;
  SetTestDeadline(context);
  return server.stub().LipBlink(&context, request, response);
}

TEST(FileRequestTest, BvhFileAnswersTheDecodedRequestAndTheCliFile) {
  InProcessServer server;
  int compared = 0;
  std::vector<std::string> files = BvhFiles();
  files.push_back(KOMA_TESTDATA_DIR "/two_joints_crlf.bvh");
  files.push_back(KOMA_TESTDATA_DIR "/unusual_channels.bvh");
  for (const std::string& path : files) {
    const std::string text = ReadTestFile(path);
    ASSERT_OK_AND_ASSIGN(const SkeletalClip clip, formats::ParseBvh(text));
    for (const v1::RetimeSkeletalRequest& options : SkeletalOptionSets(path)) {
      SCOPED_TRACE(path + " with " + options.ShortDebugString());
      v1::RetimeSkeletalRequest decoded = options;
      *decoded.mutable_motion() = convert::ToProto(clip);
      v1::RetimeSkeletalRequest file = options;
      file.set_bvh_text(text);
      v1::RetimeSkeletalResponse decoded_response, file_response;
      ASSERT_TRUE(Call(server, decoded, &decoded_response).ok());
      const grpc::Status status = Call(server, file, &file_response);
      ASSERT_TRUE(status.ok()) << status.error_message();

      // What `koma skeletal -o` writes: the decoded answer's clip on the parsed skeleton.
      ASSERT_OK_AND_ASSIGN(const SkeletalClip retimed,
                           convert::ClipFromResponse(decoded_response, clip.skeleton));
      EXPECT_EQ(file_response.bvh_text(), formats::WriteBvh(retimed));
      EXPECT_FALSE(file_response.has_motion());
      EXPECT_GT(file_response.source_frames_size(), 1);
      // Every other field is the decoded answer's.
      decoded_response.clear_motion();
      file_response.clear_bvh_text();
      EXPECT_EQ(file_response.SerializeAsString(), decoded_response.SerializeAsString());
      ++compared;
    }
  }
  EXPECT_EQ(compared, 5 * 4 + 2);
}

TEST(FileRequestTest, BvhFileWithoutReturnMotionAnswersOnlyTheTiming) {
  InProcessServer server;
  v1::RetimeSkeletalRequest request;
  request.set_bvh_text(ReadTestFile(KOMA_SAMPLES_DIR "/pitch.bvh"));
  request.set_return_motion(false);
  v1::RetimeSkeletalResponse response;
  ASSERT_TRUE(Call(server, request, &response).ok());
  EXPECT_TRUE(response.bvh_text().empty());
  EXPECT_FALSE(response.has_motion());
  EXPECT_EQ(response.source_frames_size(), 130);
}

// Files over the wire as Windows tools write them: a UTF-8 byte order mark is skipped (the same
// answer as without it), UTF-16 is refused naming the field and the encoding.
TEST(FileRequestTest, AUtf8ByteOrderMarkIsSkippedAndUtf16IsNamed) {
  InProcessServer server;
  const std::string bom = "\xEF\xBB\xBF";
  v1::RetimeSkeletalRequest plain, marked;
  plain.set_bvh_text(ReadTestFile(KOMA_SAMPLES_DIR "/pitch.bvh"));
  marked.set_bvh_text(bom + plain.bvh_text());
  v1::RetimeSkeletalResponse plain_response, marked_response;
  ASSERT_TRUE(Call(server, plain, &plain_response).ok());
  ASSERT_TRUE(Call(server, marked, &marked_response).ok());
  EXPECT_EQ(marked_response.SerializeAsString(), plain_response.SerializeAsString());

  v1::LipBlinkRequest lip_plain, lip_marked;
  lip_plain.set_motion3_json(ReadTestFile(KOMA_SAMPLES_DIR "/talk_blink.motion3.json"));
  lip_marked.set_motion3_json(bom + lip_plain.motion3_json());
  v1::LipBlinkResponse lip_plain_response, lip_marked_response;
  ASSERT_TRUE(Call(server, lip_plain, &lip_plain_response).ok());
  ASSERT_TRUE(Call(server, lip_marked, &lip_marked_response).ok());
  EXPECT_EQ(lip_marked_response.SerializeAsString(), lip_plain_response.SerializeAsString());

  v1::RetimeCurvesRequest csv_plain, csv_marked;
  csv_plain.set_csv_text("frame,A\n0,0\n1,1\n2,4\n3,9\n4,16\n5,25\n");
  csv_marked.set_csv_text(bom + csv_plain.csv_text());
  v1::RetimeCurvesResponse csv_plain_response, csv_marked_response;
  ASSERT_TRUE(Call(server, csv_plain, &csv_plain_response).ok());
  ASSERT_TRUE(Call(server, csv_marked, &csv_marked_response).ok());
  EXPECT_EQ(csv_marked_response.SerializeAsString(), csv_plain_response.SerializeAsString());

  v1::RetimeSkeletalRequest utf16;
  std::string text = "\xFF\xFE";
  for (char c : plain.bvh_text().substr(0, 64)) text += std::string{c, '\0'};
  utf16.set_bvh_text(text);
  v1::RetimeSkeletalResponse refused;
  const grpc::Status status = Call(server, utf16, &refused);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(status.error_message(),
            "bvh_text: the file is UTF-16 (little-endian, byte order mark FF FE), not UTF-8: "
            "save it as UTF-8");
}

// samples/talk_blink.motion3.json with the defaults (linked eyes, 24 fps film grid): every eye
// is open until it snaps shut. The left eye starts closing a grid frame before the right, and
// its half-closed value used to pass through: ParamEyeLOpen 1, 0.833, 1, 0 (issue 35).
TEST(FileRequestTest, TalkBlinkEyesSnapShutStraightFromOpen) {
  InProcessServer server;
  v1::LipBlinkRequest request;
  request.set_motion3_json(ReadTestFile(KOMA_SAMPLES_DIR "/talk_blink.motion3.json"));
  v1::LipBlinkResponse response;
  ASSERT_TRUE(Call(server, request, &response).ok());
  EXPECT_EQ(response.timing_fps(), 24.0);
  ASSERT_EQ(response.eyes_size(), 2);
  for (const v1::EyeTrack& eye : response.eyes()) {
    const v1::ConvertedCurve* curve = nullptr;
    for (const v1::ConvertedCurve& c : response.curves()) {
      if (c.id() == eye.id()) curve = &c;
    }
    ASSERT_NE(curve, nullptr) << eye.id();
    int snaps = 0;
    for (int f = 1; f < curve->values_size(); ++f) {
      if (curve->values(f - 1) != eye.open_level() || curve->values(f) == eye.open_level()) {
        continue;
      }
      EXPECT_EQ(curve->values(f), eye.closed_level()) << eye.id() << " frame " << f;
      ++snaps;
    }
    EXPECT_EQ(snaps, eye.blinks_size()) << eye.id();
  }
}

struct CurveFileCase {
  std::string name;
  std::string text;
  bool csv;
  double csv_fps;  // 0: unset (30)
};

// The samples and test files, plus talk_blink as CSV (written here by the CLI's writer).
std::vector<CurveFileCase> CurveFiles() {
  std::vector<CurveFileCase> cases = {
      {"arm_head.motion3.json", ReadTestFile(KOMA_SAMPLES_DIR "/arm_head.motion3.json"), false, 0},
      {"talk_blink.motion3.json", ReadTestFile(KOMA_SAMPLES_DIR "/talk_blink.motion3.json"), false,
       0},
      {"small.motion3.json", ReadTestFile(KOMA_TESTDATA_DIR "/small.motion3.json"), false, 0},
      {"curves_crlf.csv", ReadTestFile(KOMA_TESTDATA_DIR "/curves_crlf.csv"), true, 0},
      {"curves_crlf.csv at 24 fps", ReadTestFile(KOMA_TESTDATA_DIR "/curves_crlf.csv"), true, 24},
  };
  const convert::CurveInput talk = convert::ParseCurveText(cases[1].text, false, 30).value();
  std::vector<std::optional<convert::CurveReplacement>> none(talk.curves.curves.size());
  cases.push_back({"talk_blink.csv", convert::CurveOutputText(talk, none, true).value(), true, 0});
  return cases;
}

template <typename Request>
void SetFile(const CurveFileCase& file, Request* request) {
  if (file.csv) {
    request->set_csv_text(file.text);
    if (file.csv_fps != 0) request->set_csv_fps(file.csv_fps);
  } else {
    request->set_motion3_json(file.text);
  }
}

template <typename Response>
const std::string& FileOf(const Response& response, bool csv) {
  return csv ? response.csv_text() : response.motion3_json();
}

std::vector<v1::RetimeCurvesRequest> CurvesOptionSets() {
  std::vector<v1::RetimeCurvesRequest> sets(3);
  sets[1].set_timing_fps(0);
  sets[1].set_frames_per_drawing(2);
  sets[2].set_tame(1.5);
  sets[2].set_tsume(1.25);
  return sets;
}

TEST(FileRequestTest, CurveFileAnswersTheDecodedRequestAndTheCliFile) {
  InProcessServer server;
  int compared = 0;
  for (const CurveFileCase& file : CurveFiles()) {
    ASSERT_OK_AND_ASSIGN(
        const convert::CurveInput input,
        convert::ParseCurveText(file.text, file.csv, file.csv_fps == 0 ? 30 : file.csv_fps));
    for (const v1::RetimeCurvesRequest& options : CurvesOptionSets()) {
      SCOPED_TRACE(file.name + " with " + options.ShortDebugString());
      v1::RetimeCurvesRequest decoded = options;
      *decoded.mutable_curves() = convert::CurveSetToProto(input.curves);
      v1::RetimeCurvesRequest with_file = options;
      SetFile(file, &with_file);
      v1::RetimeCurvesResponse decoded_response, file_response;
      ASSERT_TRUE(Call(server, decoded, &decoded_response).ok());
      const grpc::Status status = Call(server, with_file, &file_response);
      ASSERT_TRUE(status.ok()) << status.error_message();

      // What `koma curves IN -o OUT` (OUT of IN's type) writes from the decoded answer.
      std::vector<std::optional<convert::CurveReplacement>> replacements;
      for (const v1::RetimedCurve& curve : decoded_response.curves()) {
        replacements.push_back(
            convert::CurveReplacement{{curve.values().begin(), curve.values().end()},
                                      convert::StepsFromProto(curve.stepped())});
      }
      ASSERT_OK_AND_ASSIGN(const std::string expected,
                           convert::CurveOutputText(input, replacements, file.csv));
      EXPECT_EQ(file_response.output_case(), file.csv ? v1::RetimeCurvesResponse::kCsvText
                                                      : v1::RetimeCurvesResponse::kMotion3Json);
      EXPECT_EQ(FileOf(file_response, file.csv), expected);
      file_response.clear_output();
      EXPECT_EQ(file_response.SerializeAsString(), decoded_response.SerializeAsString());
      ++compared;
    }
  }
  EXPECT_EQ(compared, 6 * 3);
}

std::vector<v1::LipBlinkRequest> LipBlinkOptionSets() {
  std::vector<v1::LipBlinkRequest> sets(3);
  sets[1].set_seed(7);
  sets[1].mutable_mouth()->set_mode(v1::MOUTH_FOLLOW);
  sets[2].set_timing_fps(0);
  sets[2].mutable_eyes()->mutable_auto_blink()->set_enabled(true);
  sets[2].mutable_eyes()->mutable_auto_blink()->set_mean_interval_s(1.0);
  return sets;
}

TEST(FileRequestTest, LipBlinkFileAnswersTheDecodedRequestAndTheCliFile) {
  InProcessServer server;
  int compared = 0;
  for (const CurveFileCase& file : CurveFiles()) {
    if (file.name.rfind("talk_blink", 0) != 0) continue;  // the files with a mouth and eyes
    ASSERT_OK_AND_ASSIGN(const convert::CurveInput input,
                         convert::ParseCurveText(file.text, file.csv, 30));
    for (const v1::LipBlinkRequest& options : LipBlinkOptionSets()) {
      SCOPED_TRACE(file.name + " with " + options.ShortDebugString());
      v1::LipBlinkRequest decoded = options;
      *decoded.mutable_curves() = convert::CurveSetToProto(input.curves);
      v1::LipBlinkRequest with_file = options;
      SetFile(file, &with_file);
      v1::LipBlinkResponse decoded_response, file_response;
      ASSERT_TRUE(Call(server, decoded, &decoded_response).ok());
      const grpc::Status status = Call(server, with_file, &file_response);
      ASSERT_TRUE(status.ok()) << status.error_message();
      ASSERT_GT(decoded_response.curves_size(), 0);

      // What `koma lipblink IN -o OUT` writes: converted curves replace theirs by id.
      std::map<std::string, size_t> index_of;
      for (size_t i = 0; i < input.curves.curves.size(); ++i) {
        index_of[input.curves.curves[i].id] = i;
      }
      std::vector<std::optional<convert::CurveReplacement>> replacements(
          input.curves.curves.size());
      for (const v1::ConvertedCurve& curve : decoded_response.curves()) {
        replacements[index_of.at(curve.id())] =
            convert::CurveReplacement{{curve.values().begin(), curve.values().end()},
                                      convert::StepsFromProto(curve.stepped())};
      }
      ASSERT_OK_AND_ASSIGN(const std::string expected,
                           convert::CurveOutputText(input, replacements, file.csv));
      EXPECT_EQ(FileOf(file_response, file.csv), expected);
      EXPECT_NE(expected, file.text);  // the mouth and eyes did change
      file_response.clear_output();
      EXPECT_EQ(file_response.SerializeAsString(), decoded_response.SerializeAsString());
      ++compared;
    }
  }
  EXPECT_EQ(compared, 2 * 3);
}

// The raw service writes a file request's answer itself (the skeletal bytes, the curves'
// slices plus the file field): its bytes equal the message path's SerializeToString.
TEST(FileRequestTest, RawAnswerBytesEqualTheMessagePath) {
  InProcessServer server;
  const server::RequestLimits limits;
  {
    v1::RetimeSkeletalRequest request;
    request.set_bvh_text(ReadTestFile(KOMA_TESTDATA_DIR "/bvh_test1.bvh"));
    v1::RetimeSkeletalResponse reference;
    ASSERT_THAT(server::HandleRetimeSkeletal(request, limits, &reference), IsOk());
    std::string answer;
    ASSERT_TRUE(
        RawUnaryCall(server, "/koma.v1.Retime/RetimeSkeletal", request.SerializeAsString(), &answer)
            .ok());
    EXPECT_FALSE(reference.bvh_text().empty());
    EXPECT_EQ(answer, reference.SerializeAsString());
  }
  for (const CurveFileCase& file : CurveFiles()) {
    SCOPED_TRACE(file.name);
    v1::RetimeCurvesRequest request;
    SetFile(file, &request);
    v1::RetimeCurvesResponse reference;
    ASSERT_THAT(server::HandleRetimeCurves(request, limits, &reference), IsOk());
    std::string answer;
    ASSERT_TRUE(
        RawUnaryCall(server, "/koma.v1.Retime/RetimeCurves", request.SerializeAsString(), &answer)
            .ok());
    EXPECT_FALSE(FileOf(reference, file.csv).empty());
    EXPECT_EQ(answer, reference.SerializeAsString());
  }
}

TEST(FileRequestTest, FilesOverTheLimitAreRefusedNamingTheFieldAndTheFlag) {
  const std::string bvh = ReadTestFile(KOMA_TESTDATA_DIR "/two_joints_crlf.bvh");
  const std::string json = ReadTestFile(KOMA_TESTDATA_DIR "/small.motion3.json");
  const std::string csv = ReadTestFile(KOMA_TESTDATA_DIR "/curves_crlf.csv");
  const int64_t limit = static_cast<int64_t>(std::max({bvh.size(), json.size(), csv.size()}));
  server::ServerConfig config;
  config.limits.max_file_bytes = limit;
  InProcessServer server(config);
  // At the limit: answered.
  const std::string padded_bvh = bvh + std::string(limit - bvh.size(), '\n');
  v1::RetimeSkeletalRequest skeletal;
  skeletal.set_bvh_text(padded_bvh);
  skeletal.set_timing_fps(0);  // 3 frames at 120 fps: too short for the 24 fps grid
  v1::RetimeSkeletalResponse skeletal_response;
  EXPECT_TRUE(Call(server, skeletal, &skeletal_response).ok());
  // One byte over: refused, for every file field of every RPC.
  const std::string over = "exceeds the server limit --max_file_bytes=" + std::to_string(limit);
  skeletal.set_bvh_text(padded_bvh + "\n");
  grpc::Status status = Call(server, skeletal, &skeletal_response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_EQ(status.error_message(), "bvh_text: " + std::to_string(limit + 1) + " bytes " + over);

  v1::RetimeCurvesRequest curves;
  curves.set_motion3_json(json + std::string(limit + 1 - json.size(), ' '));
  v1::RetimeCurvesResponse curves_response;
  status = Call(server, curves, &curves_response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_EQ(status.error_message(),
            "motion3_json: " + std::to_string(limit + 1) + " bytes " + over);
  curves.set_csv_text(csv + std::string(limit + 1 - csv.size(), '\n'));
  status = Call(server, curves, &curves_response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_EQ(status.error_message(), "csv_text: " + std::to_string(limit + 1) + " bytes " + over);

  v1::LipBlinkRequest lip;
  lip.set_motion3_json(json + std::string(limit + 1 - json.size(), ' '));
  v1::LipBlinkResponse lip_response;
  status = Call(server, lip, &lip_response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_EQ(status.error_message(),
            "motion3_json: " + std::to_string(limit + 1) + " bytes " + over);
}

TEST(FileRequestTest, ZeroMaxFileBytesRefusesEveryFile) {
  server::ServerConfig config;
  config.limits.max_file_bytes = 0;
  InProcessServer server(config);
  v1::RetimeSkeletalRequest request;
  request.set_bvh_text(ReadTestFile(KOMA_SAMPLES_DIR "/pitch.bvh"));
  v1::RetimeSkeletalResponse response;
  const grpc::Status status = Call(server, request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(status.error_message().find("--max_file_bytes=0"), std::string::npos);
}

// What a file decodes to meets the limits and checks of a decoded request, with the same
// code and message as the decoded request (so as the CLI, which sends it decoded).
TEST(FileRequestTest, DecodedLimitsAndChecksApplyToFilesWithTheSameMessages) {
  server::ServerConfig config;
  config.limits.max_values = 5000;  // pitch: 130 frames x 66 channels = 8580
  config.limits.max_joints = 8;     // bvh_test1: 24 joints
  InProcessServer server(config);
  const std::string one_frame =
      "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 3 Xposition Yposition Zposition\n"
      "\tEnd Site\n\t{\n\t\tOFFSET 0 1 0\n\t}\n}\nMOTION\nFrames: 1\nFrame Time: 0.04\n0 0 0\n";
  struct Case {
    std::string text;
    int omissions;  // -1: unset
    grpc::StatusCode code;
  };
  const std::vector<Case> cases = {
      {ReadTestFile(KOMA_SAMPLES_DIR "/pitch.bvh"), -1, grpc::StatusCode::RESOURCE_EXHAUSTED},
      {ReadTestFile(KOMA_TESTDATA_DIR "/bvh_test1.bvh"), -1, grpc::StatusCode::RESOURCE_EXHAUSTED},
      {one_frame, -1, grpc::StatusCode::INVALID_ARGUMENT},
      {ReadTestFile(KOMA_TESTDATA_DIR "/two_joints_crlf.bvh"), 1000,
       grpc::StatusCode::OUT_OF_RANGE},
  };
  for (const Case& c : cases) {
    ASSERT_OK_AND_ASSIGN(const SkeletalClip clip, formats::ParseBvh(c.text));
    v1::RetimeSkeletalRequest decoded;
    *decoded.mutable_motion() = convert::ToProto(clip);
    decoded.set_timing_fps(0);  // counts in source frames: the checks above, not the grid's
    if (c.omissions >= 0) decoded.set_omissions(c.omissions);
    v1::RetimeSkeletalRequest file = decoded;
    file.set_bvh_text(c.text);
    v1::RetimeSkeletalResponse ignored;
    const grpc::Status decoded_status = Call(server, decoded, &ignored);
    const grpc::Status file_status = Call(server, file, &ignored);
    EXPECT_EQ(decoded_status.error_code(), c.code) << decoded_status.error_message();
    EXPECT_EQ(file_status.error_code(), c.code);
    EXPECT_EQ(file_status.error_message(), decoded_status.error_message());
  }
}

TEST(FileRequestTest, CsvFpsIsCheckedAndUsed) {
  InProcessServer server;
  const std::string csv = ReadTestFile(KOMA_TESTDATA_DIR "/curves_crlf.csv");
  for (const double fps : {-1.0, -0.0 - 1e-300, std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    v1::RetimeCurvesRequest request;
    request.set_csv_text(csv);
    request.set_csv_fps(fps);
    v1::RetimeCurvesResponse response;
    const grpc::Status status = Call(server, request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << fps;
    EXPECT_EQ(status.error_message().rfind("csv_fps: ", 0), 0u) << status.error_message();
  }
  // At 24 fps the default 24 fps film grid is the curves' own rate: no grid. At the default
  // 30 it is one.
  v1::RetimeCurvesRequest request;
  request.set_csv_text(csv);
  v1::RetimeCurvesResponse response;
  ASSERT_TRUE(Call(server, request, &response).ok());
  EXPECT_EQ(response.timing_fps(), 24);
  request.set_csv_fps(24);
  ASSERT_TRUE(Call(server, request, &response).ok());
  EXPECT_EQ(response.timing_fps(), 0);
}

// With a memory budget a file request is sized by its text until parsed, then by what it
// decodes to: a file whose decoded call does not fit is refused naming the budget, even when
// its text is small (a motion3.json of a few keys over a long Duration).
TEST(FileRequestTest, FileRequestsAreSizedByTheMemoryBudgetOnceParsed) {
  server::ServerConfig config = InProcessServer::Config(2, 20'000'000);
  config.max_memory_mb = 24;  // 12 MiB of it for calls (server.cc: half the budget)
  InProcessServer server(config);
  ASSERT_NE(server.server().memory_budget(), nullptr);
  const std::string budget = "memory budget (--max_memory_mb=24";
  const std::string parsed = "this file request (the parsed file, the decoded request";

  // bvh_test3's 100 frames repeated to 2,000: 3 MB of text (9 MB to parse), 8.8 MB decoded
  // (values, world positions, returned motion) + 6 MB of text and written file.
  const std::string test3 = ReadTestFile(KOMA_TESTDATA_DIR "/bvh_test3.bvh");
  const size_t motion = test3.find("MOTION");
  const size_t frame_time = test3.find("Frame Time:", motion);
  const size_t first_frame = test3.find('\n', frame_time) + 1;
  std::istringstream frames_in(test3.substr(first_frame));
  std::vector<std::string> frames;
  for (std::string line; std::getline(frames_in, line);) {
    if (!line.empty() && line != "\r") frames.push_back(line);
  }
  ASSERT_EQ(frames.size(), 100u);
  std::string big = test3.substr(0, motion) + "MOTION\nFrames: 2000\n" +
                    test3.substr(frame_time, first_frame - frame_time);
  for (int f = 0; f < 2000; ++f) big += frames[f % 100] + "\n";
  ASSERT_GT(big.size(), 2'500'000u);
  v1::RetimeSkeletalRequest skeletal;
  skeletal.set_bvh_text(big);
  v1::RetimeSkeletalResponse skeletal_response;
  grpc::Status status = Call(server, skeletal, &skeletal_response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  EXPECT_NE(status.error_message().find(budget), std::string::npos) << status.error_message();
  EXPECT_NE(status.error_message().find(parsed), std::string::npos) << status.error_message();
  // Small files fit.
  skeletal.set_bvh_text(ReadTestFile(KOMA_SAMPLES_DIR "/pitch.bvh"));
  status = Call(server, skeletal, &skeletal_response);
  EXPECT_TRUE(status.ok()) << status.error_message();

  // 20 curves of two keys over 2,000 s at 30 fps: under 2 KB of text, 60,001 frames x 20
  // curves per-frame values (~23 MB) once decoded.
  std::string curves_json =
      R"({"Version": 3, "Meta": {"Duration": 2000, "Fps": 30, "Loop": false}, "Curves": [)";
  for (int c = 0; c < 20; ++c) {
    curves_json += (c ? ", " : "") + std::string(R"({"Target": "Parameter", "Id": "P)") +
                   std::to_string(c) + R"(", "Segments": [0, 0, 0, 2000, 1]})";
  }
  curves_json += "]}";
  ASSERT_LT(curves_json.size(), 2048u);
  v1::RetimeCurvesRequest curves;
  curves.set_motion3_json(curves_json);
  v1::RetimeCurvesResponse curves_response;
  status = Call(server, curves, &curves_response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  EXPECT_NE(status.error_message().find(parsed), std::string::npos) << status.error_message();
  v1::LipBlinkRequest lip;
  lip.set_motion3_json(curves_json);
  v1::LipBlinkResponse lip_response;
  status = Call(server, lip, &lip_response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  EXPECT_NE(status.error_message().find(parsed), std::string::npos) << status.error_message();
  // The same curves over 20 s fit.
  const size_t duration = curves_json.find("2000");
  curves_json.replace(duration, 4, "20");
  curves.set_motion3_json(curves_json);
  status = Call(server, curves, &curves_response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  // The call's reservation is released once gRPC has taken the response, which may be just
  // after the client has it: wait for that (bounded) instead of reading it at once.
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (server.server().memory_budget()->in_use() != 0 &&
         std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(server.server().memory_budget()->in_use(), 0);
}

// A file request counts its file's frames in koma_frames_processed_total (the decoded request
// carries them in frame_count; a file request only once it is parsed).
double FramesProcessed(const prometheus::Registry& registry, const std::string& method) {
  for (const prometheus::MetricFamily& family : registry.Collect()) {
    if (family.name != "koma_frames_processed_total") continue;
    for (const prometheus::ClientMetric& metric : family.metric) {
      for (const prometheus::ClientMetric::Label& label : metric.label) {
        if (label.name == "grpc_method" && label.value == method) return metric.counter.value;
      }
    }
  }
  return -1;
}

TEST(FileRequestTest, FileRequestsCountTheirFramesInTheMetrics) {
  auto registry = std::make_shared<prometheus::Registry>();
  server::ServerConfig config;
  config.metrics_registry = registry;
  InProcessServer server(config);
  v1::RetimeSkeletalRequest skeletal;
  skeletal.set_bvh_text(ReadTestFile(KOMA_SAMPLES_DIR "/pitch.bvh"));
  skeletal.set_output_rate(v1::TIMING_RATE);  // fewer output frames: the input's count
  v1::RetimeSkeletalResponse skeletal_response;
  ASSERT_TRUE(Call(server, skeletal, &skeletal_response).ok());
  EXPECT_EQ(FramesProcessed(*registry, "RetimeSkeletal"), 130);
  v1::RetimeCurvesRequest curves;
  curves.set_motion3_json(ReadTestFile(KOMA_SAMPLES_DIR "/arm_head.motion3.json"));
  v1::RetimeCurvesResponse curves_response;
  ASSERT_TRUE(Call(server, curves, &curves_response).ok());
  EXPECT_EQ(FramesProcessed(*registry, "RetimeCurves"), 91);
  v1::LipBlinkRequest lip;
  lip.set_motion3_json(ReadTestFile(KOMA_SAMPLES_DIR "/talk_blink.motion3.json"));
  v1::LipBlinkResponse lip_response;
  ASSERT_TRUE(Call(server, lip, &lip_response).ok());
  EXPECT_EQ(FramesProcessed(*registry, "LipBlink"), 121);
}

}  // namespace
}  // namespace koma::testing
