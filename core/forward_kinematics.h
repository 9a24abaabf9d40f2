// Forward kinematics from BVH channels to world joint positions.
#ifndef KOMA_CORE_FORWARD_KINEMATICS_H_
#define KOMA_CORE_FORWARD_KINEMATICS_H_

#include <vector>

#include "absl/status/statusor.h"
#include "absl/types/span.h"
#include "core/large_array.h"
#include "core/skeleton.h"
#include "core/task_runner.h"

namespace koma {

// World positions of every joint in every frame, frame-major: frame_count x joints x 3 (a
// LargeArray: core/large_array.h).
//
// Convention (the common BVH reading): a joint's local transform is
//   T(offset) * T(position channels) * R(c1) * R(c2) * ...
// where the rotation channels are applied in the order they are listed (intrinsic), angles in
// degrees; position channels add to the offset whatever their place in the list. World =
// parent world * local; a joint's position is the translation of its world transform.
// Requires ValidateSkeleton OK and values.size() == frame_count * ChannelCount.
// INVALID_ARGUMENT if the sizes disagree.
absl::StatusOr<LargeArray<double>> ComputeWorldPositions(const SkeletalClip& clip);

// The same over channel values held elsewhere (the server passes a view of the request's
// packed field, so 77 MB of a 100k-frame clip are not copied first). A long clip's frames are
// split into up to runner.Parallelism() contiguous stretches of at least kFramesPerFkThread,
// which `runner` may compute at once (core/task_runner.h); frames do not depend on each other,
// so the result is the same, bit for bit, for any runner. The result's capacity is at least
// `capacity_doubles`: a caller that needs an array of that size once the positions are freed
// can get the same memory back (koma_server's huge-page cache, platform/huge_page_pool.h)
// instead of faulting in fresh pages.
inline constexpr int kFramesPerFkThread = 16384;
absl::StatusOr<LargeArray<double>> ComputeWorldPositions(
    const Skeleton& skeleton, absl::Span<const double> values, int frame_count,
    const TaskRunner& runner = InlineTaskRunner(), size_t capacity_doubles = 0);

}  // namespace koma

#endif  // KOMA_CORE_FORWARD_KINEMATICS_H_
