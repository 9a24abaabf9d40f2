#include "server/call_footprint.h"

#include <algorithm>
#include <cstdint>

#include "formats/gltf.h"

namespace koma::server {
namespace {

// Per call, whatever its size: the arenas' first blocks, the reactor, the log record.
constexpr int64_t kFixedBytes = 64 * 1024;
constexpr int64_t kDouble = 8;
// Per frame, besides the values: source frame, drawing index, frame kind, distances (each at
// most 8 bytes) in the result and again in the response.
constexpr int64_t kPerFrameBytes = 64;

// A count the request claims, clamped to [0, cap].
int64_t Capped(int64_t count, int64_t cap) { return std::clamp<int64_t>(count, 0, cap); }

int64_t CurvesFootprint(const v1::CurveSet& curves, int64_t request_bytes,
                        const RequestLimits& limits) {
  const int64_t frames = Capped(curves.frame_count(), limits.max_values);
  const int64_t values = Capped(frames * std::max(curves.curves_size(), 1), limits.max_values);
  return kFixedBytes + request_bytes + 2 * values * kDouble + frames * kPerFrameBytes;
}

// Memory per file byte, by format: bench/format_memory.py's measured peak above the idle
// server, per MB of file (with the decoded request and the answer), rounded up with a quarter
// to spare; the JSON formats at least 24, what a JSON document of nothing but empty strings
// or objects costs nlohmann (16 bytes a value, and 40 more for the string or object, per
// 3 bytes of text). Measured (MiB per MB): BVH 5.0 (whole call), motion3.json 22.6, curve
// CSV 7.5, Spine JSON 12.1, Rhubarb JSON 16.4, WAV 2.8, a GLB's JSON chunk 58.
constexpr int64_t kBvhParseFactor = 3;
constexpr int64_t kBvhOverheadFactor = 2;
constexpr int64_t kMotion3Factor = 28;
constexpr int64_t kCsvFactor = 10;
constexpr int64_t kSpineFactor = 24;
constexpr int64_t kRhubarbFactor = 24;
constexpr int64_t kAudioFactor = 4;
// FBX: the file, koma's node tree (arrays stay encoded until asked for) and the written file.
constexpr int64_t kFbxFactor = 8;
// glTF: the bytes (and the buffers copied out of them) 3x, its JSON structure 72x.
constexpr int64_t kGltfBytesFactor = 3;
constexpr int64_t kGltfJsonFactor = 72;

int64_t Factor(FileKind kind, bool parse) {
  switch (kind) {
    case FileKind::kBvh:
      return parse ? kBvhParseFactor : kBvhOverheadFactor;
    case FileKind::kGltf:
      return kGltfBytesFactor;
    case FileKind::kFbx:
      return kFbxFactor;
    case FileKind::kMotion3:
      return kMotion3Factor;
    case FileKind::kCsv:
      return kCsvFactor;
    case FileKind::kSpine:
      return kSpineFactor;
    case FileKind::kRhubarb:
      return kRhubarbFactor;
    case FileKind::kAudio:
      return kAudioFactor;
  }
  return kMotion3Factor;
}

}  // namespace

int64_t FileParseFootprint(int64_t file_bytes, FileKind kind) {
  return kFixedBytes + Factor(kind, /*parse=*/true) * file_bytes;
}

int64_t FileOverheadFootprint(int64_t file_bytes, FileKind kind) {
  return kFixedBytes + Factor(kind, /*parse=*/false) * file_bytes;
}

int64_t GltfFootprint(std::string_view file) {
  return FileParseFootprint(static_cast<int64_t>(file.size()), FileKind::kGltf) +
         kGltfJsonFactor * formats::GltfJsonStructureBytes(file);
}

int64_t ReceivedFootprint(int64_t request_bytes) { return kFixedBytes + 2 * request_bytes; }

int64_t ExpectedFootprint(const v1::RetimeSkeletalRequest& request, int64_t /*request_bytes*/,
                          const RequestLimits& limits) {
  if (request.input_case() == v1::RetimeSkeletalRequest::kBvhText) {
    return FileParseFootprint(static_cast<int64_t>(request.bvh_text().size()), FileKind::kBvh);
  }
  if (request.input_case() == v1::RetimeSkeletalRequest::kGltf) {
    return GltfFootprint(request.gltf());
  }
  if (request.input_case() == v1::RetimeSkeletalRequest::kFbx) {
    return FileParseFootprint(static_cast<int64_t>(request.fbx().size()), FileKind::kFbx);
  }
  // The received bytes are freed once parsed (ParseRequest in retime_service.cc); the
  // skeleton and options are small beside the values.
  const v1::SkeletalMotion& motion = request.motion();
  const int64_t frames = Capped(motion.frame_count(), limits.max_values);
  const int64_t joints = Capped(motion.skeleton().joints_size(), limits.max_joints);
  const int64_t values =
      Capped(std::max(motion.channels().values_size(), motion.positions().values_size()),
             limits.max_values);
  const int64_t positions = Capped(frames * joints * 3, limits.max_values);
  const bool returns_motion = !request.has_return_motion() || request.return_motion();
  return kFixedBytes + values * kDouble + positions * kDouble +
         (returns_motion ? values * kDouble : 0) + frames * kPerFrameBytes;
}

namespace {

template <typename Request>
FileKind CurveFileKindOf(const Request& request) {
  if (request.input_case() == Request::kCsvText) return FileKind::kCsv;
  if (request.input_case() == Request::kSpineJson) return FileKind::kSpine;
  return FileKind::kMotion3;
}

}  // namespace

FileKind CurveFileKind(const v1::RetimeCurvesRequest& request) { return CurveFileKindOf(request); }
FileKind CurveFileKind(const v1::LipBlinkRequest& request) { return CurveFileKindOf(request); }

int64_t ExpectedFootprint(const v1::RetimeCurvesRequest& request, int64_t request_bytes,
                          const RequestLimits& limits) {
  if (request.input_case() != v1::RetimeCurvesRequest::kCurves &&
      request.input_case() != v1::RetimeCurvesRequest::INPUT_NOT_SET) {
    return FileParseFootprint(request_bytes, CurveFileKind(request));
  }
  return CurvesFootprint(request.curves(), request_bytes, limits);
}

int64_t ExpectedFootprint(const v1::LipBlinkRequest& request, int64_t request_bytes,
                          const RequestLimits& limits) {
  // A voice is held as received while it is decoded (its analysis, a few dozen bytes per film
  // grid frame, is reserved by the voice handler once the header gives its length); what the
  // rest of the request needs is estimated on the rest of its bytes.
  const int64_t audio_bytes = static_cast<int64_t>(request.audio().size());
  const int64_t cue_bytes = static_cast<int64_t>(request.rhubarb_cues().size());
  request_bytes -= audio_bytes + cue_bytes;
  // The motion koma writes for a voice alone is small beside the voice.
  const int64_t voice = (audio_bytes > 0 ? FileParseFootprint(audio_bytes, FileKind::kAudio) : 0) +
                        (cue_bytes > 0 ? FileParseFootprint(cue_bytes, FileKind::kRhubarb) : 0);
  if (request.input_case() == v1::LipBlinkRequest::INPUT_NOT_SET && voice > 0) return voice;
  if (request.input_case() != v1::LipBlinkRequest::kCurves &&
      request.input_case() != v1::LipBlinkRequest::INPUT_NOT_SET) {
    return voice + FileParseFootprint(request_bytes, CurveFileKind(request));
  }
  return voice + CurvesFootprint(request.curves(), request_bytes, limits);
}

}  // namespace koma::server
