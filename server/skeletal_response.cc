#include "server/skeletal_response.h"

#include <cstring>

#include "absl/base/config.h"
#include "server/wire_bytes.h"

namespace koma::server {
namespace {

using wire::CodedOutputStream;
using wire::DoubleIsWritten;
using wire::kLength;
using wire::LengthField;
using wire::Tag;
using wire::WireFormatLite;
using wire::WriteLength;

constexpr uint8_t kResponseMotion = Tag(13, kLength);
// SkeletalMotion
constexpr uint8_t kSkeleton = Tag(1, kLength);
constexpr uint8_t kFrameTime = Tag(2, wire::kFixed64);
constexpr uint8_t kFrameCount = Tag(3, wire::kVarint);
// ChannelValues / JointPositions
constexpr uint8_t kValues = Tag(1, kLength);

}  // namespace

SkeletalResponseEncoder::SkeletalResponseEncoder(const v1::RetimeSkeletalResponse& head,
                                                 const v1::RetimeSkeletalResponse& tail,
                                                 bool with_motion, const v1::SkeletalMotion& source,
                                                 double frame_time, bool channel_form,
                                                 int per_frame,
                                                 const std::vector<int32_t>& source_frames)
    : head_(head),
      tail_(tail),
      with_motion_(with_motion),
      source_(source),
      frame_time_(frame_time),
      per_frame_(per_frame),
      source_frames_(source_frames),
      values_(channel_form ? &source.channels().values() : &source.positions().values()),
      data_field_(channel_form ? v1::SkeletalMotion::kChannelsFieldNumber
                               : v1::SkeletalMotion::kPositionsFieldNumber) {
  head_bytes_ = head_.ByteSizeLong();  // also caches the sizes SerializeWithCachedSizes uses
  tail_bytes_ = tail_.ByteSizeLong();
  size_ = head_bytes_ + tail_bytes_;
  if (!with_motion_) return;
  skeleton_bytes_ = source_.skeleton().ByteSizeLong();
  values_bytes_ = sizeof(double) * source_frames_.size() * static_cast<size_t>(per_frame_);
  data_bytes_ = values_bytes_ == 0 ? 0 : LengthField(values_bytes_);  // packed: empty left out
  const int32_t frame_count = static_cast<int32_t>(source_frames_.size());
  motion_bytes_ =
      LengthField(skeleton_bytes_) + (DoubleIsWritten(frame_time_) ? 1 + sizeof(double) : 0) +
      (frame_count != 0 ? 1 + CodedOutputStream::VarintSize32SignExtended(frame_count) : 0) +
      LengthField(data_bytes_);  // the oneof's message, present even when empty
  size_ += LengthField(motion_bytes_);
}

void SkeletalResponseEncoder::WriteTo(uint8_t* out) const {
  out = head_.SerializeWithCachedSizesToArray(out);
  if (with_motion_) out = WriteMotion(out);
  tail_.SerializeWithCachedSizesToArray(out);
}

uint8_t* SkeletalResponseEncoder::WriteMotion(uint8_t* out) const {
  out = WriteLength(kResponseMotion, motion_bytes_, out);
  out = WriteLength(kSkeleton, skeleton_bytes_, out);
  out = source_.skeleton().SerializeWithCachedSizesToArray(out);
  if (DoubleIsWritten(frame_time_)) {
    *out++ = kFrameTime;
    out = WireFormatLite::WriteDoubleNoTagToArray(frame_time_, out);
  }
  const int32_t frame_count = static_cast<int32_t>(source_frames_.size());
  if (frame_count != 0) {
    *out++ = kFrameCount;
    out = CodedOutputStream::WriteVarint32SignExtendedToArray(frame_count, out);
  }
  out = WriteLength(Tag(data_field_, WireFormatLite::WIRETYPE_LENGTH_DELIMITED), data_bytes_, out);
  if (values_bytes_ == 0) return out;
  out = WriteLength(kValues, values_bytes_, out);
  const double* values = values_->data();
  for (const int32_t frame : source_frames_) {
#ifdef ABSL_IS_LITTLE_ENDIAN
    // A packed double is its 8 little-endian bytes: a frame is one copy.
    const size_t frame_bytes = sizeof(double) * static_cast<size_t>(per_frame_);
    std::memcpy(out, values + static_cast<size_t>(frame) * per_frame_, frame_bytes);
    out += frame_bytes;
#else
    for (int k = 0; k < per_frame_; ++k) {
      out = WireFormatLite::WriteDoubleNoTagToArray(
          values[static_cast<size_t>(frame) * per_frame_ + k], out);
    }
#endif
  }
  return out;
}

}  // namespace koma::server
