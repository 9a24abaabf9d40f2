// RetimeSkeletalResponse wire bytes with the returned motion's values copied straight from the
// request's frames, without building the response's motion as a message first. The motion is
// most of a response (a 100k-frame, 31-joint clip: 74 MB), and as a message it was copied
// twice: frame by frame into the response, then again by the serialiser; this writes each
// output frame once, into the bytes gRPC sends.
//
// The bytes are exactly what a RetimeSkeletalResponse with the same fields and the motion
// filled in gives from SerializeToString: protobuf writes fields in number order, so the
// fields before the motion (1-12, `head`), the motion (13), then those after it (14 and up:
// the film grid's and the duplicates' fates, `tail`); the frame values (the data oneof, 4 or 5) are the motion's last
// field (tests/server/skeletal_response_test.cc compares the two).
#ifndef KOMA_SERVER_SKELETAL_RESPONSE_H_
#define KOMA_SERVER_SKELETAL_RESPONSE_H_

#include <cstddef>
#include <cstdint>
#include <vector>

#include "koma/v1/retime.pb.h"

namespace koma::server {

// The response's bytes: `head` (fields 1-12; motion and later fields unset) followed, if
// `with_motion`, by a motion with `source`'s skeleton (always present, possibly empty),
// `frame_time`, frame_count = source_frames.size(), and the frame values of source frames
// source_frames[0], [1], ... as channels (`channel_form`) or positions, from `source`'s values
// of that form (`per_frame` values each), then `tail` (fields 14 and up only). Sizes
// everything once on construction; the arguments must outlive the encoder and stay unchanged.
class SkeletalResponseEncoder {
 public:
  SkeletalResponseEncoder(const v1::RetimeSkeletalResponse& head,
                          const v1::RetimeSkeletalResponse& tail, bool with_motion,
                          const v1::SkeletalMotion& source, double frame_time, bool channel_form,
                          int per_frame, const std::vector<int32_t>& source_frames);

  // The serialised response's length in bytes.
  size_t size() const { return size_; }

  // Writes exactly size() bytes at `out`.
  void WriteTo(uint8_t* out) const;

 private:
  // Writes the motion field (13) at `out`; returns the end.
  uint8_t* WriteMotion(uint8_t* out) const;

  const v1::RetimeSkeletalResponse& head_;
  const v1::RetimeSkeletalResponse& tail_;
  const bool with_motion_;
  const v1::SkeletalMotion& source_;
  const double frame_time_;
  const int per_frame_;
  const std::vector<int32_t>& source_frames_;
  const google::protobuf::RepeatedField<double>* values_;  // the source's frame values
  int data_field_ = 0;         // SkeletalMotion's field number of the data: 4 or 5
  size_t head_bytes_ = 0;      // head, serialised
  size_t tail_bytes_ = 0;      // tail, serialised
  size_t skeleton_bytes_ = 0;  // the motion's skeleton message (body)
  size_t values_bytes_ = 0;    // the packed values (body)
  size_t data_bytes_ = 0;      // the ChannelValues / JointPositions message (body)
  size_t motion_bytes_ = 0;    // the SkeletalMotion message (body)
  size_t size_ = 0;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_SKELETAL_RESPONSE_H_
