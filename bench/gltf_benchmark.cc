// RetimeSkeletal on a glTF file against the same motion as BVH text, both carried in the
// request (`gltf`, `bvh_text`) and answered in kind: parse the received bytes, read the file,
// sample / run FK, retime, write the file, encode the response. In process (no transport: the
// two requests are about the same size, so gRPC's part would be about equal), single-threaded.
// The motion is koma_load's synthetic clip (bench/load/load_request.h): a random 60-joint tree,
// each rotation channel a sum of two sinusoids; as glTF the same tree with one node per joint,
// a skin over all of them, the rotations as quaternions (the BVH's Z, X, Y order composed) and
// the root's translation, one LINEAR key per frame as a DCC's bake writes.
#include <benchmark/benchmark.h>

#include <grpcpp/support/byte_buffer.h>
#include <grpcpp/support/slice.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "bench/load/load_request.h"
#include "core/skeleton.h"
#include "formats/bvh.h"
#include "google/protobuf/arena.h"
#include "server/request_limits.h"
#include "server/skeletal_parse.h"
#include "server/skeletal_request.h"
#include "tests/testing/gltf_builder.h"

namespace koma {
namespace {

constexpr int kJoints = 60;

using Quat = std::array<double, 4>;

Quat AxisAngle(int axis, double degrees) {
  const double half = degrees * 3.14159265358979323846 / 360;
  Quat q = {0, 0, 0, std::cos(half)};
  q[static_cast<size_t>(axis)] = std::sin(half);
  return q;
}

Quat Multiply(const Quat& a, const Quat& b) {
  return {a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
          a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
          a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
          a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
}

struct Files {
  std::string bvh;
  std::string glb;
};

// The synthetic clip as BVH text and as a GLB.
Files MakeFiles(int frames) {
  const v1::RetimeSkeletalRequest synthetic =
      load::SyntheticSkeletal(frames, kJoints, /*positions=*/false, /*seed=*/1);
  const v1::SkeletalMotion& motion = synthetic.motion();
  SkeletalClip clip;
  clip.frame_time = motion.frame_time();
  clip.frame_count = motion.frame_count();
  clip.values.assign(motion.channels().values().begin(), motion.channels().values().end());
  for (const v1::Joint& in : motion.skeleton().joints()) {
    Joint joint;
    joint.name = in.name();
    joint.parent = in.parent();
    joint.offset = {in.offset().x(), in.offset().y(), in.offset().z()};
    for (const std::string& channel : in.channels()) joint.channels.push_back(*ParseChannelName(channel));
    clip.skeleton.joints.push_back(joint);
  }
  Files files;
  files.bvh = formats::WriteBvh(clip);

  testing::TestGltf g;
  using Json = nlohmann::ordered_json;
  g.json["asset"] = {{"version", "2.0"}};
  Json nodes = Json::array();
  for (int j = 0; j < kJoints; ++j) {
    const Joint& joint = clip.skeleton.joints[static_cast<size_t>(j)];
    Json node = {{"name", joint.name},
                 {"translation", {joint.offset.x, joint.offset.y, joint.offset.z}}};
    Json children = Json::array();
    for (int c = j + 1; c < kJoints; ++c) {
      if (clip.skeleton.joints[static_cast<size_t>(c)].parent == j) children.push_back(c);
    }
    if (!children.empty()) node["children"] = children;
    nodes.push_back(node);
  }
  g.json["nodes"] = nodes;
  g.json["scenes"] = Json::array({{{"nodes", {0}}}});
  Json joints = Json::array();
  for (int j = 0; j < kJoints; ++j) joints.push_back(j);
  g.json["skins"] = Json::array({{{"joints", joints}}});
  std::vector<float> times;
  for (int f = 0; f < frames; ++f) times.push_back(static_cast<float>(f * clip.frame_time));
  const int input = g.AddFloats(times, "SCALAR", true);
  const int channels = ChannelCount(clip.skeleton);
  Json samplers = Json::array();
  Json animation_channels = Json::array();
  auto add = [&](int node, const char* path, const std::vector<float>& values, const char* type) {
    samplers.push_back({{"input", input}, {"output", g.AddFloats(values, type)}});
    animation_channels.push_back(
        {{"sampler", samplers.size() - 1}, {"target", {{"node", node}, {"path", path}}}});
  };
  std::vector<float> root_translation;
  for (int f = 0; f < frames; ++f) {
    const double* v = clip.values.data() + static_cast<size_t>(f) * static_cast<size_t>(channels);
    const Vec3& o = clip.skeleton.joints[0].offset;
    root_translation.insert(root_translation.end(), {static_cast<float>(o.x + v[0]),
                                                     static_cast<float>(o.y + v[1]),
                                                     static_cast<float>(o.z + v[2])});
  }
  add(0, "translation", root_translation, "VEC3");
  int first_channel = 0;
  for (int j = 0; j < kJoints; ++j) {
    const Joint& joint = clip.skeleton.joints[static_cast<size_t>(j)];
    std::vector<float> rotation;
    for (int f = 0; f < frames; ++f) {
      Quat q = {0, 0, 0, 1};
      for (size_t c = 0; c < joint.channels.size(); ++c) {
        const ChannelKind kind = joint.channels[c];
        if (kind < ChannelKind::kXRotation) continue;
        const double degrees =
            clip.values[static_cast<size_t>(f) * static_cast<size_t>(channels) +
                        static_cast<size_t>(first_channel) + c];
        q = Multiply(q, AxisAngle(static_cast<int>(kind) - 3, degrees));
      }
      for (double x : q) rotation.push_back(static_cast<float>(x));
    }
    add(j, "rotation", rotation, "VEC4");
    first_channel += static_cast<int>(joint.channels.size());
  }
  g.json["animations"] = Json::array({{{"name", "take"},
                                       {"channels", animation_channels},
                                       {"samplers", samplers}}});
  files.glb = g.Glb();
  return files;
}

grpc::ByteBuffer RequestBytes(const v1::RetimeSkeletalRequest& request) {
  const std::string bytes = request.SerializeAsString();
  grpc::Slice slice(bytes.data(), bytes.size());
  return grpc::ByteBuffer(&slice, 1);
}

void RunFile(benchmark::State& state, bool glb) {
  const Files files = MakeFiles(static_cast<int>(state.range(0)));
  v1::RetimeSkeletalRequest request;
  if (glb) {
    request.set_gltf(files.glb);
  } else {
    request.set_bvh_text(files.bvh);
  }
  const grpc::ByteBuffer bytes = RequestBytes(request);
  server::RequestLimits limits;
  limits.threads_per_call = 1;
  for (auto _ : state) {
    google::protobuf::Arena arena;
    auto* parsed = google::protobuf::Arena::CreateMessage<v1::RetimeSkeletalRequest>(&arena);
    if (!server::ParseSkeletalRequest(bytes, parsed).ok()) state.SkipWithError("parse");
    server::SkeletalAnswer answer;
    const absl::Status status = server::RetimeSkeletalAnswer(*parsed, limits, &answer);
    if (!status.ok()) state.SkipWithError(std::string(status.message()).c_str());
    benchmark::DoNotOptimize(answer.bytes.begin());
  }
  state.counters["request_MB"] = static_cast<double>(request.ByteSizeLong()) / 1e6;
}

void BM_SkeletalFileBvh(benchmark::State& state) { RunFile(state, false); }
void BM_SkeletalFileGlb(benchmark::State& state) { RunFile(state, true); }

// Args: frames (60 joints).
BENCHMARK(BM_SkeletalFileBvh)->Arg(300)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SkeletalFileGlb)->Arg(300)->Arg(10000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace koma
