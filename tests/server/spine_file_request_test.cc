// Spine skeletons over the wire (RetimeCurvesRequest.spine_json / spine_animation): the answer
// is the decoded request's answer plus the skeleton the `koma` CLI writes from it, byte for
// byte; errors name the request field and the JSON path.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "convert/curve_text.h"
#include "convert/curves_convert.h"
#include "formats/spine.h"
#include "tests/formats/test_files.h"
#include "tests/server/in_process_server.h"
#include "tests/testing/status_matchers.h"

namespace koma::testing {
namespace {

std::string SpineText(const std::string& name) {
  return formats::ReadTestFile(KOMA_TESTDATA_DIR "/spine/" + name);
}

grpc::Status Call(InProcessServer& server, const v1::RetimeCurvesRequest& request,
                  v1::RetimeCurvesResponse* response) {
  grpc::ClientContext context;
  SetTestDeadline(context);
  return server.stub().RetimeCurves(&context, request, response);
}

struct SpineCase {
  std::string file;
  std::string animation;
};

TEST(SpineFileRequestTest, AnswersTheDecodedRequestAndTheCliFile) {
  InProcessServer server;
  const SpineCase kCases[] = {{"matt-3.7.json", "shake_head"}, {"matt-3.7.json", "walk"},
                              {"hero-3.8.json", "walk"},       {"hero-3.8.json", "idle"},
                              {"hero-4.1.json", "walk"},       {"hero-4.2.json", ""}};
  for (const SpineCase& c : kCases) {
    for (const double timing_fps : {24.0, 0.0}) {
      SCOPED_TRACE(c.file + " " + c.animation + " at " + std::to_string(timing_fps));
      const std::string text = SpineText(c.file);
      ASSERT_OK_AND_ASSIGN(const convert::CurveInput input,
                           convert::ParseSpineText(text, c.animation));
      v1::RetimeCurvesRequest decoded;
      decoded.set_timing_fps(timing_fps);
      decoded.set_tame(1.5);
      *decoded.mutable_curves() = convert::CurveSetToProto(input.curves);
      v1::RetimeCurvesRequest with_file;
      with_file.set_timing_fps(timing_fps);
      with_file.set_tame(1.5);
      with_file.set_spine_json(text);
      with_file.set_spine_animation(c.animation);
      v1::RetimeCurvesResponse decoded_response, file_response;
      ASSERT_TRUE(Call(server, decoded, &decoded_response).ok());
      const grpc::Status status = Call(server, with_file, &file_response);
      ASSERT_TRUE(status.ok()) << status.error_message();
      std::vector<std::optional<convert::CurveReplacement>> replacements;
      for (const v1::RetimedCurve& curve : decoded_response.curves()) {
        replacements.push_back(convert::ReplacementFromProto(curve));
      }
      ASSERT_OK_AND_ASSIGN(const std::string expected,
                           convert::CurveOutputText(input, replacements, false));
      EXPECT_EQ(file_response.output_case(), v1::RetimeCurvesResponse::kSpineJson);
      EXPECT_EQ(file_response.spine_json(), expected);
      file_response.clear_output();
      EXPECT_EQ(file_response.SerializeAsString(), decoded_response.SerializeAsString());
    }
  }
}

TEST(SpineFileRequestTest, BadFilesAndAnimationsNameTheField) {
  InProcessServer server;
  struct Bad {
    std::string json;
    std::string animation;
    std::string message;  // the start of the error message
  };
  std::string bad_curve = SpineText("hero-4.1.json");
  bad_curve.replace(bad_curve.find("\"curve\": \"stepped\""), 18, "\"curve\": \"smooth\"");
  const Bad kBad[] = {
      {"{", "", "spine_json: invalid JSON at byte 2: parse error at line 1, column 2"},
      {"", "", "spine_json: invalid JSON at byte 1"},
      {bad_curve, "walk",
       "spine_json: animations.walk.bones.torso.rotate[1].curve: unknown curve kind \"smooth\""},
      {R"({"skeleton":{"spine":"3.5.51"},"bones":[]})", "",
       "spine_json: skeleton.spine: \"3.5.51\" is not a Spine version koma reads"},
      {SpineText("hero-3.8.json"), "",
       "spine_animation: name the animation to retime: the skeleton has 2 (\"walk\", \"idle\")"},
      {SpineText("hero-3.8.json"), "run", "spine_animation: no animation named \"run\""},
      {SpineText("hero-3.8.json"), "blink",
       "spine_animation: animation \"blink\" has no bone rotate, translate, scale or shear keys"},
  };
  for (const Bad& bad : kBad) {
    v1::RetimeCurvesRequest request;
    request.set_spine_json(bad.json);
    request.set_spine_animation(bad.animation);
    v1::RetimeCurvesResponse response;
    const grpc::Status status = Call(server, request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << bad.message;
    EXPECT_EQ(status.error_message().rfind(bad.message, 0), 0u)
        << status.error_message() << "\nwant: " << bad.message;
  }
}

}  // namespace
}  // namespace koma::testing
