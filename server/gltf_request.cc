#include "server/gltf_request.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "convert/gltf_convert.h"
#include "core/gltf_animation.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "formats/error_text.h"
#include "formats/gltf.h"
#include "server/call_footprint.h"
#include "server/call_reservation.h"

namespace koma::server {
namespace {

constexpr double kMaxSourceFps = 1000.0;

absl::Status InField(const absl::Status& status, absl::string_view field) {
  return absl::Status(status.code(), absl::StrCat(field, ": ", status.message()));
}

// The animations to retime, in file order.
absl::StatusOr<std::vector<int>> PickAnimations(const v1::RetimeSkeletalRequest& options,
                                                const formats::GltfDocument& document) {
  std::vector<int> picked;
  if (options.gltf_retime_none()) {
    if (options.gltf_animations_size() > 0) {
      return absl::InvalidArgumentError(
          "gltf_animations: given with gltf_retime_none; give one or the other");
    }
    return picked;
  }
  const int count = static_cast<int>(document.animations.size());
  if (options.gltf_animations_size() == 0) {
    for (int a = 0; a < count; ++a) picked.push_back(a);
    return picked;
  }
  std::set<int> chosen;
  for (int i = 0; i < options.gltf_animations_size(); ++i) {
    const std::string& wanted = options.gltf_animations(i);
    const std::string field = absl::StrCat("gltf_animations[", i, "]");
    int found = -1;
    for (int a = 0; a < count && found < 0; ++a) {
      if (document.animations[static_cast<size_t>(a)].name == wanted) found = a;
    }
    int index = 0;
    if (found < 0 && absl::SimpleAtoi(wanted, &index) && index >= 0 && index < count) found = index;
    if (found < 0) {
      std::string names;
      for (int a = 0; a < count && a < 20; ++a) {
        absl::StrAppend(&names, a == 0 ? "" : ", ", a, " ",
                        formats::QuoteForError(document.animations[static_cast<size_t>(a)].name));
      }
      return absl::InvalidArgumentError(absl::StrCat(
          field, ": ", formats::QuoteForError(wanted),
          " is neither the name nor the index of an "
          "animation of the file (",
          count, count == 1 ? " animation" : " animations", count > 0 ? ": " : "", names, ")"));
    }
    if (!chosen.insert(found).second) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": ", formats::QuoteForError(wanted),
                                                     " picks animation ", found, " a second time"));
    }
  }
  picked.assign(chosen.begin(), chosen.end());
  return picked;
}

// The output keys of one retimed animation: STEP keys where a drawing starts (and at the last
// output frame), or LINEAR keys at every output frame; each the source pose of the frame shown.
formats::GltfAnimationKeys KeysFor(const GltfClip& clip, int animation, double start,
                                   double source_fps, double output_fps,
                                   const v1::RetimeSkeletalResponse& timing, bool linear) {
  formats::GltfAnimationKeys keys;
  keys.animation = animation;
  keys.linear = linear;
  std::vector<int> shown;  // per key, the source frame
  const int outputs = timing.source_frames_size();
  for (int t = 0; t < outputs; ++t) {
    const bool starts = t == 0 || timing.source_frames(t) != timing.source_frames(t - 1);
    if (!linear && !starts && t != outputs - 1) continue;
    keys.times.push_back(start + static_cast<double>(t) / output_fps);
    shown.push_back(timing.source_frames(t));
  }
  keys.values.resize(clip.channels.size());
  for (size_t c = 0; c < clip.channels.size(); ++c) {
    const GltfChannel& channel = clip.channels[c];
    const GltfSampler& sampler = clip.samplers[static_cast<size_t>(channel.sampler)];
    std::vector<double>& values = keys.values[c];
    values.resize(shown.size() * static_cast<size_t>(sampler.width));
    for (size_t k = 0; k < shown.size(); ++k) {
      const double time = start + static_cast<double>(shown[k]) / source_fps;
      EvaluateGltfSampler(sampler, channel.path == GltfPath::kRotation, time,
                          GltfSnapSeconds(time, source_fps),
                          values.data() + k * static_cast<size_t>(sampler.width));
    }
  }
  return keys;
}

}  // namespace

absl::Status HandleRetimeSkeletalGltf(const v1::RetimeSkeletalRequest& request,
                                      const RequestLimits& limits,
                                      v1::RetimeSkeletalResponse* response,
                                      SkeletalAnswer* described) {
  const std::string& bytes = request.gltf();
  if (static_cast<int64_t>(bytes.size()) > limits.max_file_bytes) {
    return absl::ResourceExhaustedError(
        absl::StrCat("gltf: ", bytes.size(),
                     " bytes exceeds the server limit --max_file_bytes=", limits.max_file_bytes));
  }
  const v1::RetimeSkeletalRequest& options = request;
  const double fps_option = options.gltf_source_fps();
  if (!std::isfinite(fps_option) || fps_option < 0 || fps_option > kMaxSourceFps) {
    return absl::InvalidArgumentError(
        absl::StrCat("gltf_source_fps: ", fps_option,
                     " must be finite and in (0, 1000] frames per second (0: from the keys)"));
  }
  if (options.gltf_keys() != v1::GLTF_KEY_MODE_UNSPECIFIED &&
      options.gltf_keys() != v1::GLTF_KEYS_STEP && options.gltf_keys() != v1::GLTF_KEYS_LINEAR) {
    return absl::InvalidArgumentError(absl::StrCat(
        "gltf_keys: ", static_cast<int>(options.gltf_keys()), " is not a GltfKeyMode"));
  }
  formats::GltfReadLimits read_limits;
  read_limits.max_keys = limits.max_values;
  read_limits.max_nodes = limits.max_gltf_nodes;
  read_limits.max_animations = limits.max_gltf_animations;
  absl::StatusOr<formats::GltfDocument> document = formats::ReadGltf(bytes, read_limits);
  if (!document.ok()) return InField(document.status(), "gltf");
  KOMA_ASSIGN_OR_RETURN(const std::vector<int> picked, PickAnimations(options, *document));
  if (document->joints.empty() && !picked.empty()) {
    return absl::InvalidArgumentError("gltf: the file has no nodes to measure motion on");
  }
  const bool linear = options.gltf_keys() == v1::GLTF_KEYS_LINEAR;
  // Each animation's request: the options without the file, copied from `base` (the file is
  // megabytes; copying it once per animation made a file with many animations quadratic).
  v1::RetimeSkeletalRequest base;
  base.CopyFrom(request);
  base.clear_gltf();
  base.clear_gltf_animations();
  base.clear_gltf_retime_none();
  base.clear_gltf_source_fps();
  base.clear_gltf_keys();
  base.clear_gltf_keep_original();
  base.set_return_motion(false);
  // Every animation's sampling first: the frames of all of them together are the work
  // (each is retimed on its own), bounded by --max_values as one animation's are.
  struct Sampling {
    int animation;
    double fps;
    int64_t frames;
  };
  std::vector<Sampling> plan;
  const int64_t joints = static_cast<int64_t>(document->joints.size());
  const int64_t per_frame = std::max<int64_t>(1, joints * 3);
  int64_t total_frames = 0;
  for (int a : picked) {
    const GltfClip& clip = document->animations[static_cast<size_t>(a)].clip;
    if (clip.channels.empty()) continue;  // nothing moves: left as it is
    const double fps = fps_option > 0 ? fps_option : GltfAutoSourceFps(clip);
    const int64_t frames = GltfFrameCount(clip, fps);
    if (frames < 2) continue;  // a single pose: nothing to retime, left as it is
    // Divided, not multiplied: frames may be saturated near 2^62 (GltfFrameCount).
    if (frames > limits.max_values / per_frame) {
      return absl::ResourceExhaustedError(
          absl::StrCat("gltf: animations[", a, "]: ", frames, " frames at ", fps, " fps x ", joints,
                       " joints x 3 exceeds the server limit --max_values=", limits.max_values));
    }
    total_frames += frames;
    if (total_frames > limits.max_values / per_frame) {
      return absl::ResourceExhaustedError(absl::StrCat(
          "gltf: the animations up to animations[", a, "] sample to ", total_frames,
          " frames in all x ", joints, " joints x 3, which exceeds the server limit --max_values=",
          limits.max_values, "; retime fewer at a time (gltf_animations)"));
    }
    plan.push_back({a, fps, frames});
  }
  if (request.has_given_timing() && plan.size() != 1) {
    // One timing fits one clip: which animation it is for must not be a guess.
    return absl::InvalidArgumentError(absl::StrCat(
        "given_timing: a given timing applies to one animation, but this request retimes ",
        plan.size(), "; name one in gltf_animations"));
  }
  std::vector<formats::GltfAnimationKeys> all_keys;
  const int64_t file_footprint = GltfFootprint(bytes);  // a pass over the file: once
  StopPoll stop(/*steps_between_checks=*/1);  // an animation is a retime call's worth of work
  for (const Sampling& sampling : plan) {
    if (stop.Stop()) return stop.status();
    const int a = sampling.animation;
    const double fps = sampling.fps;
    const int64_t frames = sampling.frames;
    const formats::GltfAnimation& animation = document->animations[static_cast<size_t>(a)];
    const std::string field = absl::StrCat("gltf: animations[", a, "]");
    const GltfClip& clip = animation.clip;
    const double start = GltfClipStart(clip);
    v1::RetimeSkeletalRequest decoded;
    decoded.CopyFrom(base);
    *decoded.mutable_motion() = convert::GltfMotion(*document, a, fps, frames);
    KOMA_RETURN_IF_ERROR(GrowCallReservation(
        file_footprint + ExpectedFootprint(decoded, static_cast<int64_t>(bytes.size()), limits),
        "this glTF request (the parsed file, the sampled joints, work, response)"));
    v1::GltfAnimationTiming* timing = response->add_gltf_animations();
    absl::Status retimed = HandleRetimeSkeletal(decoded, limits, timing->mutable_timing());
    if (!retimed.ok()) return InField(retimed, field);
    timing->set_index(a);
    timing->set_name(animation.name);
    timing->set_source_fps(fps);
    timing->set_start_s(start);
    timing->set_frame_count(static_cast<int32_t>(frames));
    for (const v1::Joint& joint : decoded.motion().skeleton().joints()) {
      timing->add_joints(joint.name());
    }
    const v1::RetimeSkeletalResponse& map = timing->timing();
    const double output_fps =
        map.timing_fps() > 0 && request.output_rate() == v1::TIMING_RATE ? map.timing_fps() : fps;
    timing->set_output_fps(output_fps);
    all_keys.push_back(KeysFor(clip, a, start, fps, output_fps, map, linear));
    timing->set_keys_written(static_cast<int32_t>(all_keys.back().times.size()));
    if (described != nullptr && response->gltf_animations_size() == 1) {
      described->frames = static_cast<int>(frames);
      described->joints = static_cast<int>(joints);
    }
  }
  if (response->gltf_animations_size() > 0) {
    // The first retimed animation's timing in the top-level fields (the BVH answer's fields).
    v1::RetimeSkeletalResponse head = response->gltf_animations(0).timing();
    head.mutable_gltf_animations()->Swap(response->mutable_gltf_animations());
    response->Swap(&head);
  }
  const bool return_motion = !request.has_return_motion() || request.return_motion();
  if (!return_motion) return absl::OkStatus();
  absl::StatusOr<std::string> written =
      formats::WriteGltf(*document, all_keys, options.gltf_keep_original());
  if (!written.ok()) return InField(written.status(), "gltf");
  response->set_gltf(*std::move(written));
  return absl::OkStatus();
}

}  // namespace koma::server
