// RetimeSkeletal with a glTF file (server/gltf_request.h) through the in-process server: the
// timing equals the positions-form request of the sampled joints, the written file shows at
// every output frame the source pose of the frame the timing map names (STEP keys only where a
// drawing starts), and the options and errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "convert/gltf_convert.h"
#include "core/gltf_animation.h"
#include "formats/gltf.h"
#include "formats/gltf_internal.h"
#include "server/skeletal_request.h"
#include "tests/server/in_process_server.h"
#include "tests/testing/gltf_builder.h"
#include "tests/testing/status_matchers.h"

namespace koma::testing {
namespace {

using ::testing::ElementsAre;
using ::testing::ElementsAreArray;
using ::testing::HasSubstr;
using ::testing::StartsWith;
using Json = nlohmann::ordered_json;

v1::RetimeSkeletalResponse Call(InProcessServer& server, const v1::RetimeSkeletalRequest& request,
                                grpc::Status* status_out = nullptr) {
  v1::RetimeSkeletalResponse response;
  const grpc::Status status = CallRpc(server.stub(), request, &response);
  if (status_out != nullptr) {
    *status_out = status;
  } else {
    EXPECT_TRUE(status.ok()) << status.error_message();
  }
  return response;
}

// Every channel of `written` animation `a`, evaluated at each output frame, equals `source`'s
// at the source frame the timing map shows there; with STEP, no value changes inside a drawing.
void ExpectShowsTheTimingMap(const formats::GltfDocument& source,
                             const formats::GltfDocument& written, int a,
                             const v1::GltfAnimationTiming& timing) {
  const GltfClip& before = source.animations[static_cast<size_t>(timing.index())].clip;
  const GltfClip& after = written.animations[static_cast<size_t>(a)].clip;
  ASSERT_EQ(after.channels.size(), before.channels.size());
  const double start = timing.start_s();
  const auto& shown = timing.timing().source_frames();
  ASSERT_GT(shown.size(), 1);
  for (size_t c = 0; c < before.channels.size(); ++c) {
    EXPECT_EQ(after.channels[c].node, before.channels[c].node);
    EXPECT_EQ(after.channels[c].path, before.channels[c].path);
    const bool rotation = before.channels[c].path == GltfPath::kRotation;
    const GltfSampler& src = before.samplers[static_cast<size_t>(before.channels[c].sampler)];
    const GltfSampler& out = after.samplers[static_cast<size_t>(after.channels[c].sampler)];
    std::vector<double> want(static_cast<size_t>(src.width)), got(want.size());
    for (int t = 0; t < shown.size(); ++t) {
      const double source_time = start + shown[t] / timing.source_fps();
      EvaluateGltfSampler(src, rotation, source_time, GltfSnapSeconds(source_time, 30), want.data());
      // A player samples output frame t at exactly t / fps seconds from the start.
      EvaluateGltfSampler(out, rotation, start + t / timing.output_fps(), 0, got.data());
      for (size_t i = 0; i < want.size(); ++i) {
        ASSERT_NEAR(got[i], want[i], 1e-6) << "channel " << c << " output frame " << t;
      }
      if (out.interpolation == GltfInterpolation::kStep && t + 1 < shown.size() &&
          shown[t + 1] == shown[t]) {
        // Inside a drawing (halfway to the next frame) nothing moves.
        std::vector<double> inside(want.size());
        EvaluateGltfSampler(out, rotation, start + (t + 0.5) / timing.output_fps(), 0,
                            inside.data());
        EXPECT_EQ(inside, got) << "channel " << c << " inside drawing at " << t;
      }
    }
  }
}

TEST(GltfRequestTest, TimingIsThePositionsRequestsAndTheFileShowsIt) {
  InProcessServer server;
  for (const bool glb : {true, false}) {
    for (const v1::OutputRate rate : {v1::SOURCE_RATE, v1::TIMING_RATE}) {
      for (const v1::GltfKeyMode keys : {v1::GLTF_KEYS_STEP, v1::GLTF_KEYS_LINEAR}) {
        SCOPED_TRACE(::testing::Message() << "glb " << glb << " rate " << rate << " keys " << keys);
        const std::string bytes = glb ? ArmGltf().Glb() : ArmGltf().GltfText();
        v1::RetimeSkeletalRequest request;
        request.set_gltf(bytes);
        request.set_output_rate(rate);
        request.set_gltf_keys(keys);
        request.set_omissions(3);
        const v1::RetimeSkeletalResponse response = Call(server, request);
        ASSERT_EQ(response.gltf_animations_size(), 1);
        const v1::GltfAnimationTiming& animation = response.gltf_animations(0);
        EXPECT_EQ(animation.name(), "Wave");
        EXPECT_EQ(animation.source_fps(), 30);
        EXPECT_EQ(animation.frame_count(), 61);
        EXPECT_THAT(animation.joints(), ElementsAre("Hips", "Arm", "Hand"));
        EXPECT_EQ(animation.output_fps(), rate == v1::TIMING_RATE ? 24 : 30);

        // The same timing as the positions-form request of the sampled joints.
        ASSERT_OK_AND_ASSIGN(const formats::GltfDocument source, formats::ReadGltf(bytes));
        v1::RetimeSkeletalRequest decoded = request;
        decoded.clear_gltf();
        decoded.clear_gltf_keys();
        decoded.set_return_motion(false);
        *decoded.mutable_motion() = convert::GltfMotion(source, 0, 30, 61);
        v1::RetimeSkeletalResponse expected;
        ASSERT_THAT(server::HandleRetimeSkeletal(decoded, {}, &expected), IsOk());
        EXPECT_EQ(animation.timing().SerializeAsString(), expected.SerializeAsString());
        EXPECT_THAT(response.source_frames(), ElementsAreArray(expected.source_frames()));
        EXPECT_GT(expected.omissions_applied(), 0);

        ASSERT_OK_AND_ASSIGN(const formats::GltfDocument written,
                             formats::ReadGltf(response.gltf()));
        EXPECT_EQ(written.binary, glb);
        ASSERT_EQ(written.animations.size(), 1u);
        ExpectShowsTheTimingMap(source, written, 0, animation);
        // STEP: a key per drawing plus the last frame; LINEAR: one per output frame.
        int drawings = 0;
        for (int t = 0; t < expected.source_frames_size(); ++t) {
          drawings += t == 0 || expected.source_frames(t) != expected.source_frames(t - 1);
        }
        const int outputs = expected.source_frames_size();
        const bool last_starts = outputs > 1 && expected.source_frames(outputs - 1) !=
                                                    expected.source_frames(outputs - 2);
        EXPECT_EQ(animation.keys_written(),
                  keys == v1::GLTF_KEYS_LINEAR ? outputs : drawings + (last_starts ? 0 : 1));
        EXPECT_EQ(written.animations[0].clip.samplers[0].times.size(),
                  static_cast<size_t>(animation.keys_written()));
      }
    }
  }
}

TEST(GltfRequestTest, KeepOriginalAddsTheAnimeAnimationBeside) {
  InProcessServer server;
  v1::RetimeSkeletalRequest request;
  request.set_gltf(ArmGltf().Glb());
  request.set_gltf_keep_original(true);
  const v1::RetimeSkeletalResponse response = Call(server, request);
  ASSERT_OK_AND_ASSIGN(const formats::GltfDocument source, formats::ReadGltf(request.gltf()));
  ASSERT_OK_AND_ASSIGN(const formats::GltfDocument written, formats::ReadGltf(response.gltf()));
  ASSERT_EQ(written.animations.size(), 2u);
  EXPECT_EQ(written.animations[1].name, "Wave.anime");
  EXPECT_EQ(written.animations[0].clip.samplers[0].values,
            source.animations[0].clip.samplers[0].values);
  ExpectShowsTheTimingMap(source, written, 1, response.gltf_animations(0));
}

TEST(GltfRequestTest, RetimeNoneKeepsSceneExtensionsExtrasAndMeshBytes) {
  InProcessServer server;
  for (const bool glb : {true, false}) {
    const std::string bytes = glb ? ArmGltf().Glb() : ArmGltf().GltfText();
    v1::RetimeSkeletalRequest request;
    request.set_gltf(bytes);
    request.set_gltf_retime_none(true);
    const v1::RetimeSkeletalResponse response = Call(server, request);
    EXPECT_EQ(response.gltf_animations_size(), 0);
    EXPECT_EQ(response.source_frames_size(), 0);
    ASSERT_OK_AND_ASSIGN(const formats::GltfDocument in, formats::ReadGltf(bytes));
    ASSERT_OK_AND_ASSIGN(const formats::GltfDocument out, formats::ReadGltf(response.gltf()));
    EXPECT_EQ(out.json, in.json);
    EXPECT_EQ(out.buffers, in.buffers);
  }
}

TEST(GltfRequestTest, PicksAnimationsByNameOrIndex) {
  InProcessServer server;
  // Two animations: the arm's, and a copy named "Idle" driving only the hips.
  TestGltf g = ArmGltf();
  Json idle = g.json["animations"][0];
  idle["name"] = "Idle";
  idle["channels"] = Json::array({idle["channels"][1]});
  idle["channels"][0]["sampler"] = 0;
  idle["samplers"] = Json::array({idle["samplers"][1]});
  g.json["animations"].push_back(idle);
  v1::RetimeSkeletalRequest request;
  request.set_gltf(g.Glb());
  v1::RetimeSkeletalResponse all = Call(server, request);
  ASSERT_EQ(all.gltf_animations_size(), 2);
  EXPECT_EQ(all.gltf_animations(1).name(), "Idle");
  request.add_gltf_animations("Idle");
  v1::RetimeSkeletalResponse idle_only = Call(server, request);
  ASSERT_EQ(idle_only.gltf_animations_size(), 1);
  EXPECT_EQ(idle_only.gltf_animations(0).index(), 1);
  ASSERT_OK_AND_ASSIGN(const formats::GltfDocument source, formats::ReadGltf(request.gltf()));
  ASSERT_OK_AND_ASSIGN(const formats::GltfDocument written, formats::ReadGltf(idle_only.gltf()));
  // "Wave" untouched (same values), "Idle" retimed.
  EXPECT_EQ(written.animations[0].clip.samplers[0].values,
            source.animations[0].clip.samplers[0].values);
  ExpectShowsTheTimingMap(source, written, 1, idle_only.gltf_animations(0));
  request.clear_gltf_animations();
  request.add_gltf_animations("0");
  EXPECT_EQ(Call(server, request).gltf_animations(0).name(), "Wave");
}

TEST(GltfRequestTest, SparseKeysAreSampledAt30AndANodeTreeWithoutSkinUsesEveryNode) {
  // A VRM Animation-like file: no skin, no mesh, a rotation keyed every 0.5 s for 4 s.
  TestGltf g;
  g.json["asset"] = {{"version", "2.0"}};
  g.json["extensionsUsed"] = {"VRMC_vrm_animation"};
  g.json["extensions"] = {{"VRMC_vrm_animation", {{"specVersion", "1.0"},
                                                  {"humanoid", {{"humanBones", {{"hips", {{"node", 0}}}}}}}}}};
  g.json["nodes"] = Json::array({{{"name", "hips"}, {"children", {1}}},
                                 {{"name", "spine"}, {"translation", {0, 1, 0}}}});
  std::vector<float> times, rotation;
  for (int k = 0; k <= 8; ++k) {
    times.push_back(0.5f * k);
    const double half = (k % 2 ? 40.0 : 0.0) * 3.14159265358979323846 / 360;
    rotation.insert(rotation.end(), {static_cast<float>(std::sin(half)), 0, 0,
                                     static_cast<float>(std::cos(half))});
  }
  const int input = g.AddFloats(times, "SCALAR", true);
  const int output = g.AddFloats(rotation, "VEC4");
  g.json["animations"] = Json::array(
      {{{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "rotation"}}}}}},
        {"samplers", {{{"input", input}, {"output", output}}}}}});
  InProcessServer server;
  v1::RetimeSkeletalRequest request;
  request.set_gltf(g.Glb());
  const v1::RetimeSkeletalResponse response = Call(server, request);
  ASSERT_EQ(response.gltf_animations_size(), 1);
  EXPECT_EQ(response.gltf_animations(0).source_fps(), 30);
  EXPECT_EQ(response.gltf_animations(0).frame_count(), 121);
  EXPECT_THAT(response.gltf_animations(0).joints(), ElementsAre("hips", "spine"));
  ASSERT_OK_AND_ASSIGN(const formats::GltfDocument source, formats::ReadGltf(request.gltf()));
  ASSERT_OK_AND_ASSIGN(const formats::GltfDocument written, formats::ReadGltf(response.gltf()));
  EXPECT_EQ(written.json["extensions"], source.json["extensions"]);
  ExpectShowsTheTimingMap(source, written, 0, response.gltf_animations(0));
  // An explicit source rate wins.
  request.set_gltf_source_fps(10);
  EXPECT_EQ(Call(server, request).gltf_animations(0).frame_count(), 41);
}

struct BadGltf {
  bool small;  // on the server with --max_file_bytes=100000, --max_gltf_nodes=3
  const char* what;
  std::function<void(v1::RetimeSkeletalRequest&)> change;
  grpc::StatusCode code;
  const char* message;
};

TEST(GltfRequestTest, BadRequestsNameTheFieldAndTheJsonPath) {
  server::ServerConfig config;
  config.limits.max_file_bytes = 100000;
  config.limits.max_gltf_nodes = 3;
  InProcessServer small(config);
  InProcessServer server;
  const std::vector<BadGltf> table = {
      {false, "source rate", [](auto& r) { r.set_gltf_source_fps(-1); },
       grpc::StatusCode::INVALID_ARGUMENT, "gltf_source_fps: -1 must be finite"},
      {false, "unknown animation", [](auto& r) { r.add_gltf_animations("Run"); },
       grpc::StatusCode::INVALID_ARGUMENT,
       "gltf_animations[0]: \"Run\" is neither the name nor the index of an animation "
       "of the file (1 animation: 0 \"Wave\")"},
      {false, "twice",
       [](auto& r) {
         r.add_gltf_animations("Wave");
         r.add_gltf_animations("0");
       },
       grpc::StatusCode::INVALID_ARGUMENT, "gltf_animations[1]: \"0\" picks animation 0 a second time"},
      {false, "truncated", [](auto& r) { r.set_gltf(r.gltf().substr(0, 40)); },
       grpc::StatusCode::INVALID_ARGUMENT, "gltf: GLB header: length"},
      {true, "too many nodes", [](auto&) {}, grpc::StatusCode::INVALID_ARGUMENT,
       "gltf: nodes: 4 nodes exceeds the limit of 3"},
      {true, "too large", [](auto& r) { r.set_gltf(r.gltf() + std::string(100000, ' ')); },
       grpc::StatusCode::RESOURCE_EXHAUSTED, "gltf: 1"},
  };
  for (const BadGltf& row : table) {
    v1::RetimeSkeletalRequest request;
    request.set_gltf(ArmGltf().Glb());
    row.change(request);
    grpc::Status status;
    Call(row.small ? small : server, request, &status);
    EXPECT_EQ(status.error_code(), row.code) << row.what << ": " << status.error_message();
    EXPECT_THAT(status.error_message(), StartsWith(row.message)) << row.what;
  }
  // A weight per joint is checked as for any skeleton.
  v1::RetimeSkeletalRequest request;
  request.set_gltf(ArmGltf().Glb());
  request.add_joint_weights(1);
  grpc::Status status;
  Call(server, request, &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), StartsWith("gltf: animations[0]: joint_weights"));
}

}  // namespace
}  // namespace koma::testing
