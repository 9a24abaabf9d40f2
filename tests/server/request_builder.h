// Small valid RetimeSkeletal requests for the server tests, to be broken one field at a time.
#ifndef KOMA_TESTS_SERVER_REQUEST_BUILDER_H_
#define KOMA_TESTS_SERVER_REQUEST_BUILDER_H_

#include <cmath>

#include "koma/v1/retime.pb.h"

namespace koma::testing {

// 3 joints (root: 6 channels; two children: 3 rotations each) = 12 channels; `frames` frames
// of a swing that is slow, then fast, then slow.
inline v1::RetimeSkeletalRequest MakeSkeletalRequest(int frames = 10) {
  v1::RetimeSkeletalRequest request;
  v1::SkeletalMotion* motion = request.mutable_motion();
  v1::Skeleton* skeleton = motion->mutable_skeleton();
  const char* names[] = {"Hips", "Arm", "Hand"};
  for (int j = 0; j < 3; ++j) {
    v1::Joint* joint = skeleton->add_joints();
    joint->set_name(names[j]);
    joint->set_parent(j - 1);
    joint->mutable_offset()->set_y(j == 0 ? 0.0 : 10.0);
    if (j == 0) {
      for (const char* c : {"Xposition", "Yposition", "Zposition"}) joint->add_channels(c);
    }
    for (const char* c : {"Zrotation", "Xrotation", "Yrotation"}) joint->add_channels(c);
  }
  skeleton->mutable_joints(2)->add_end_sites()->set_y(5.0);
  motion->set_frame_time(1.0 / 24.0);
  motion->set_frame_count(frames);
  auto* values = motion->mutable_channels()->mutable_values();
  for (int f = 0; f < frames; ++f) {
    const double s = static_cast<double>(f) / (frames - 1);
    const double eased = s * s * (3.0 - 2.0 * s);  // slow-fast-slow
    for (int c = 0; c < 12; ++c) values->Add(c < 3 ? 0.5 * c : 90.0 * eased * (1 + c % 3));
  }
  return request;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_SERVER_REQUEST_BUILDER_H_
