#include "server/call_footprint.h"

#include <algorithm>
#include <cstdint>

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

// File bytes -> memory, upper bounds of the measured ratios (call_footprint.h).
constexpr int64_t kBvhParseFactor = 3;
constexpr int64_t kBvhOverheadFactor = 2;
constexpr int64_t kCurveFileFactor = 12;

}  // namespace

int64_t FileParseFootprint(int64_t file_bytes, bool bvh) {
  return kFixedBytes + (bvh ? kBvhParseFactor : kCurveFileFactor) * file_bytes;
}

int64_t FileOverheadFootprint(int64_t file_bytes, bool bvh) {
  return kFixedBytes + (bvh ? kBvhOverheadFactor : kCurveFileFactor) * file_bytes;
}

int64_t ReceivedFootprint(int64_t request_bytes) { return kFixedBytes + 2 * request_bytes; }

int64_t ExpectedFootprint(const v1::RetimeSkeletalRequest& request, int64_t /*request_bytes*/,
                          const RequestLimits& limits) {
  if (request.input_case() == v1::RetimeSkeletalRequest::kBvhText) {
    return FileParseFootprint(static_cast<int64_t>(request.bvh_text().size()), /*bvh=*/true);
  }
  if (request.input_case() == v1::RetimeSkeletalRequest::kGltf) {
    // The bytes, tinygltf's model and the JSON document (each about the file), the buffers.
    return FileParseFootprint(static_cast<int64_t>(request.gltf().size()), /*bvh=*/true);
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

int64_t ExpectedFootprint(const v1::RetimeCurvesRequest& request, int64_t request_bytes,
                          const RequestLimits& limits) {
  if (request.input_case() != v1::RetimeCurvesRequest::kCurves &&
      request.input_case() != v1::RetimeCurvesRequest::INPUT_NOT_SET) {
    return FileParseFootprint(request_bytes, /*bvh=*/false);
  }
  return CurvesFootprint(request.curves(), request_bytes, limits);
}

int64_t ExpectedFootprint(const v1::LipBlinkRequest& request, int64_t request_bytes,
                          const RequestLimits& limits) {
  // A voice is held as received while it is decoded (its analysis, a few dozen bytes per film
  // grid frame, is reserved by the voice handler once the header gives its length); what the
  // rest of the request needs is estimated on the rest of its bytes.
  const int64_t voice_bytes =
      static_cast<int64_t>(request.audio().size() + request.rhubarb_cues().size());
  request_bytes -= voice_bytes;
  if (request.input_case() == v1::LipBlinkRequest::INPUT_NOT_SET && voice_bytes > 0) {
    return kFixedBytes + 2 * voice_bytes;  // the motion koma writes is small beside it
  }
  if (request.input_case() != v1::LipBlinkRequest::kCurves &&
      request.input_case() != v1::LipBlinkRequest::INPUT_NOT_SET) {
    return voice_bytes + FileParseFootprint(request_bytes, /*bvh=*/false);
  }
  return voice_bytes + CurvesFootprint(request.curves(), request_bytes, limits);
}

}  // namespace koma::server
