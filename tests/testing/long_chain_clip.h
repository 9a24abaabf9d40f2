// A five-joint chain with random rotations (and a root translation), long enough for forward
// kinematics to split its frames: shared by the core test of the split and the platform test
// that runs the split on real threads.
#ifndef KOMA_TESTS_TESTING_LONG_CHAIN_CLIP_H_
#define KOMA_TESTS_TESTING_LONG_CHAIN_CLIP_H_

#include <cstddef>
#include <string>
#include <vector>

#include "core/skeleton.h"
#include "core/split_mix64.h"

namespace koma::testing {

inline Skeleton FiveJointChain() {
  Skeleton skeleton;
  for (int j = 0; j < 5; ++j) {
    Joint joint;
    joint.name = "j" + std::to_string(j);
    joint.parent = j - 1;
    joint.offset = {1.0, 2.0 + j, -0.5};
    joint.channels = {ChannelKind::kZRotation, ChannelKind::kXRotation, ChannelKind::kYRotation};
    if (j == 0) joint.channels.insert(joint.channels.begin(), ChannelKind::kXPosition);
    skeleton.joints.push_back(joint);
  }
  return skeleton;
}

// `frames` frames of channel values for `skeleton`, uniform in [-360, 360) degrees (units).
inline std::vector<double> RandomChannelValues(const Skeleton& skeleton, int frames,
                                               SplitMix64& rng) {
  std::vector<double> values(static_cast<size_t>(frames) * ChannelCount(skeleton));
  for (double& v : values) v = (rng.Unit() - 0.5) * 720.0;
  return values;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_TESTING_LONG_CHAIN_CLIP_H_
