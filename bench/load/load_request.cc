#include "bench/load/load_request.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "absl/strings/str_cat.h"
#include "client/curve_files.h"
#include "client/curves_convert.h"
#include "client/files.h"
#include "client/skeletal_convert.h"
#include "core/split_mix64.h"
#include "formats/bvh.h"

namespace koma::load {
namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr char kService[] = "/koma.v1.Retime/";

// One smooth channel: the sum of two sinusoids with periods of 15-200 frames.
struct Wave {
  double amplitude[2];  // channel unit (degrees or length unit)
  double period[2];     // frames
  double phase[2];      // radians
  double Value(int frame) const {
    double v = 0.0;
    for (int k = 0; k < 2; ++k) v += amplitude[k] * std::sin(kTwoPi * frame / period[k] + phase[k]);
    return v;
  }
};

Wave RandomWave(SplitMix64& rng, double amplitude) {
  Wave w{};
  for (int k = 0; k < 2; ++k) {
    w.amplitude[k] = amplitude * (0.2 + 0.8 * rng.Unit());
    w.period[k] = 15.0 + 185.0 * rng.Unit();
    w.phase[k] = kTwoPi * rng.Unit();
  }
  return w;
}

// A random tree (each joint's parent an earlier joint) with BVH channels: the root has
// positions and rotations, the others rotations only (31 joints -> 96 channels).
v1::Skeleton SyntheticSkeleton(int joints, SplitMix64& rng, bool with_channels) {
  v1::Skeleton skeleton;
  for (int j = 0; j < joints; ++j) {
    v1::Joint* joint = skeleton.add_joints();
    joint->set_name(absl::StrCat("joint", j));
    joint->set_parent(j == 0 ? -1 : rng.Int(std::max(0, j - 4), j - 1));
    joint->mutable_offset()->set_x(20.0 * rng.Unit() - 10.0);  // length unit
    joint->mutable_offset()->set_y(20.0 * rng.Unit());
    joint->mutable_offset()->set_z(20.0 * rng.Unit() - 10.0);
    if (!with_channels) continue;
    if (j == 0) {
      for (const char* c : {"Xposition", "Yposition", "Zposition"}) joint->add_channels(c);
    }
    for (const char* c : {"Zrotation", "Xrotation", "Yrotation"}) joint->add_channels(c);
  }
  return skeleton;
}

// `values` frame-major, `width` values per frame, each column one wave.
void FillWaves(int frames, int width, double amplitude, SplitMix64& rng,
               google::protobuf::RepeatedField<double>* values) {
  std::vector<Wave> waves;
  for (int c = 0; c < width; ++c) waves.push_back(RandomWave(rng, amplitude));
  values->Resize(frames * width, 0.0);
  for (int f = 0; f < frames; ++f) {
    for (int c = 0; c < width; ++c) values->Set(f * width + c, waves[c].Value(f));
  }
}

absl::StatusOr<LoadRequest> FromFile(const LoadOptions& o) {
  LoadRequest request;
  if (o.rpc == "skeletal") {
    auto text = client::ReadFile(o.input);
    if (!text.ok()) return text.status();
    auto clip = formats::ParseBvh(*text);
    if (!clip.ok()) {
      return absl::Status(clip.status().code(),
                          absl::StrCat(o.input, ": ", clip.status().message()));
    }
    v1::RetimeSkeletalRequest message;
    *message.mutable_motion() = client::ToProto(*clip);
    if (o.max_hold) message.set_max_hold(*o.max_hold);
    request.bytes = message.SerializeAsString();
    request.description = absl::StrCat(o.input, " (", clip->frame_count, " frames x ",
                                       clip->skeleton.joints.size(), " joints)");
    return request;
  }
  auto input = client::ReadCurveInput(o.input, o.csv_fps, client::CurveFormat::kAuto, o.rpc);
  if (!input.ok()) return input.status();
  request.description = absl::StrCat(o.input, " (", input->curves.curves.size(), " curves x ",
                                     input->curves.frame_count, " frames)");
  if (o.rpc == "curves") {
    v1::RetimeCurvesRequest message;
    *message.mutable_curves() = client::CurveSetToProto(input->curves);
    request.bytes = message.SerializeAsString();
  } else {
    v1::LipBlinkRequest message;
    *message.mutable_curves() = client::CurveSetToProto(input->curves);
    request.bytes = message.SerializeAsString();
  }
  return request;
}

}  // namespace

v1::RetimeSkeletalRequest SyntheticSkeletal(int frames, int joints, bool positions, uint64_t seed) {
  SplitMix64 rng(seed);
  v1::RetimeSkeletalRequest request;
  v1::SkeletalMotion* motion = request.mutable_motion();
  *motion->mutable_skeleton() = SyntheticSkeleton(joints, rng, !positions);
  motion->set_frame_time(1.0 / 24.0);  // seconds
  motion->set_frame_count(frames);
  if (positions) {
    FillWaves(frames, 3 * joints, 30.0, rng, motion->mutable_positions()->mutable_values());
  } else {
    FillWaves(frames, 3 * joints + 3, 30.0, rng, motion->mutable_channels()->mutable_values());
  }
  return request;
}

// Pose-to-pose keyframes like curves_benchmark.cc: every curve keyed at the same poses, 6-14
// frames apart, linear segments, values in [-30, 30] (degrees).
v1::RetimeCurvesRequest SyntheticCurves(int curves, int frames, uint64_t seed) {
  SplitMix64 rng(seed);
  std::vector<int> poses = {0};
  while (poses.back() < frames - 1)
    poses.push_back(std::min(poses.back() + rng.Int(6, 14), frames - 1));
  v1::RetimeCurvesRequest request;
  v1::CurveSet* set = request.mutable_curves();
  set->set_fps(30.0);
  set->set_frame_count(frames);
  for (int c = 0; c < curves; ++c) {
    v1::Curve* curve = set->add_curves();
    curve->set_id(absl::StrCat("ParamSynthetic", c));
    curve->mutable_start()->set_value(60.0 * rng.Unit() - 30.0);
    for (size_t p = 1; p < poses.size(); ++p) {
      v1::CurveSegment* segment = curve->add_segments();
      segment->set_type(v1::SEGMENT_LINEAR);
      segment->mutable_end()->set_frame(poses[p]);
      segment->mutable_end()->set_value(60.0 * rng.Unit() - 30.0);
    }
  }
  return request;
}

// Dense curves: ParamMouthOpenY talks 2 s of every 3 s (0-1), ParamEyeLOpen/ROpen blink
// (3 frames at 0) every 3-5 s, then `curves - 3` ignored ParamSyntheticN curves.
v1::LipBlinkRequest SyntheticLipBlink(int curves, int frames, uint64_t seed) {
  SplitMix64 rng(seed);
  v1::LipBlinkRequest request;
  v1::CurveSet* set = request.mutable_curves();
  set->set_fps(30.0);
  set->set_frame_count(frames);
  const char* const kIds[] = {"ParamMouthOpenY", "ParamEyeLOpen", "ParamEyeROpen"};
  std::vector<int> blinks;
  for (int f = rng.Int(90, 150); f + 3 < frames; f += rng.Int(90, 150)) blinks.push_back(f);
  for (int c = 0; c < std::max(curves, 1); ++c) {
    v1::Curve* curve = set->add_curves();
    curve->set_id(c < 3 ? kIds[c] : absl::StrCat("ParamSynthetic", c));
    auto* samples = curve->mutable_samples();
    samples->Resize(frames, 1.0);
    if (c == 0) {
      const Wave wave = RandomWave(rng, 0.5);
      for (int f = 0; f < frames; ++f) {
        const bool speech = f % 90 < 60;
        samples->Set(f, speech ? std::clamp(0.5 + wave.Value(f * 7), 0.0, 1.0) : 0.0);
      }
    } else if (c < 3) {
      for (int b : blinks) std::fill(samples->begin() + b, samples->begin() + b + 3, 0.0);
    }
  }
  return request;
}

absl::StatusOr<LoadRequest> BuildLoadRequest(const LoadOptions& o) {
  if (!o.input.empty()) {
    auto request = FromFile(o);
    if (request.ok())
      request->method = absl::StrCat(kService, o.rpc == "skeletal" ? "RetimeSkeletal"
                                               : o.rpc == "curves" ? "RetimeCurves"
                                                                   : "LipBlink");
    return request;
  }
  LoadRequest request;
  if (o.rpc == "skeletal") {
    request.method = absl::StrCat(kService, "RetimeSkeletal");
    v1::RetimeSkeletalRequest message =
        SyntheticSkeletal(o.frames, o.joints, o.form == "positions", o.seed);
    if (o.max_hold) message.set_max_hold(*o.max_hold);
    request.bytes = message.SerializeAsString();
    request.description =
        absl::StrCat("synthetic ", o.frames, " frames x ", o.joints, " joints (", o.form, ")");
  } else if (o.rpc == "curves") {
    request.method = absl::StrCat(kService, "RetimeCurves");
    request.bytes = SyntheticCurves(o.curves, o.frames, o.seed).SerializeAsString();
    request.description = absl::StrCat("synthetic ", o.curves, " curves x ", o.frames, " frames");
  } else {
    request.method = absl::StrCat(kService, "LipBlink");
    request.bytes = SyntheticLipBlink(o.curves, o.frames, o.seed).SerializeAsString();
    request.description =
        absl::StrCat("synthetic ", std::max(o.curves, 1), " curves x ", o.frames, " frames");
  }
  return request;
}

}  // namespace koma::load
