#include "server/call_footprint.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <algorithm>
#include <cstdint>

#include "formats/format_table.h"
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

// glTF's JSON structure, beside its bytes (formats/format_table.cc's row): 72 bytes per byte,
// tinygltf's model and nlohmann's document of the JSON without its data URIs and long strings
// (measured: a GLB's JSON chunk 58 MiB per MB).
constexpr int64_t kGltfJsonFactor = 72;

}  // namespace

int64_t FileParseFootprint(int64_t file_bytes, formats::FormatId format) {
  return kFixedBytes + formats::FormatOf(format).parse_bytes_per_byte * file_bytes;
}

int64_t FileOverheadFootprint(int64_t file_bytes, formats::FormatId format) {
  return kFixedBytes + formats::FormatOf(format).kept_bytes_per_byte * file_bytes;
}

int64_t GltfFootprint(std::string_view file) {
  return FileParseFootprint(static_cast<int64_t>(file.size()), formats::FormatId::kGltf) +
         kGltfJsonFactor * formats::GltfJsonStructureBytes(file);
}

int64_t ReceivedFootprint(int64_t request_bytes) { return kFixedBytes + 2 * request_bytes; }

int64_t ExpectedFootprint(const v1::RetimeSkeletalRequest& request, int64_t /*request_bytes*/,
                          const RequestLimits& limits) {
  if (request.input_case() == v1::RetimeSkeletalRequest::kBvhText) {
    return FileParseFootprint(static_cast<int64_t>(request.bvh_text().size()),
                              formats::FormatId::kBvh);
  }
  if (request.input_case() == v1::RetimeSkeletalRequest::kGltf) {
    return GltfFootprint(request.gltf());
  }
  if (request.input_case() == v1::RetimeSkeletalRequest::kFbx) {
    return FileParseFootprint(static_cast<int64_t>(request.fbx().size()), formats::FormatId::kFbx);
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

// The format of the file the request's `input` carries: the format table's row of the field
// set (motion3.json when none is).
formats::FormatId CurveFileKindOf(const google::protobuf::Message& request) {
  const google::protobuf::Descriptor* message = request.GetDescriptor();
  const google::protobuf::FieldDescriptor* set =
      request.GetReflection()->GetOneofFieldDescriptor(request, message->FindOneofByName("input"));
  const formats::FormatRow* row =
      set == nullptr ? nullptr : formats::FormatOfRequestField(message->name(), set->name());
  return row == nullptr ? formats::FormatId::kMotion3 : row->id;
}

}  // namespace

formats::FormatId CurveFileKind(const v1::RetimeCurvesRequest& request) {
  return CurveFileKindOf(request);
}
formats::FormatId CurveFileKind(const v1::LipBlinkRequest& request) {
  return CurveFileKindOf(request);
}

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
  const int64_t voice =
      (audio_bytes > 0 ? FileParseFootprint(audio_bytes, formats::FormatId::kAudio) : 0) +
      (cue_bytes > 0 ? FileParseFootprint(cue_bytes, formats::FormatId::kRhubarb) : 0);
  if (request.input_case() == v1::LipBlinkRequest::INPUT_NOT_SET && voice > 0) return voice;
  if (request.input_case() != v1::LipBlinkRequest::kCurves &&
      request.input_case() != v1::LipBlinkRequest::INPUT_NOT_SET) {
    return voice + FileParseFootprint(request_bytes, CurveFileKind(request));
  }
  return voice + CurvesFootprint(request.curves(), request_bytes, limits);
}

}  // namespace koma::server
