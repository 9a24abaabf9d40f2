#include "core/skeleton.h"

#include <array>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace koma {
namespace {

constexpr std::array<std::string_view, 6> kChannelNames = {
    "Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation"};

bool IsFinite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string Vec3String(const Vec3& v) { return absl::StrCat("(", v.x, ", ", v.y, ", ", v.z, ")"); }

// Follows parents from `start`; true when the chain comes back to a joint already seen.
bool ParentChainLoops(const Skeleton& skeleton, int start) {
  const int n = static_cast<int>(skeleton.joints.size());
  int current = start;
  for (int steps = 0; steps <= n; ++steps) {
    current = skeleton.joints[current].parent;
    if (current < 0 || current >= n) return false;
    if (current == start) return true;
  }
  return true;  // longer than the joint count: some loop further up
}

}  // namespace

std::string_view ChannelName(ChannelKind kind) {
  return kChannelNames[static_cast<size_t>(kind)];
}

absl::StatusOr<ChannelKind> ParseChannelName(std::string_view name) {
  for (size_t i = 0; i < kChannelNames.size(); ++i) {
    if (kChannelNames[i] == name) return static_cast<ChannelKind>(i);
  }
  return absl::InvalidArgumentError(absl::StrCat(
      "unknown channel name \"", std::string(name),
      "\" (expected Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation)"));
}

int ChannelCount(const Skeleton& skeleton) {
  int count = 0;
  for (const Joint& joint : skeleton.joints) count += static_cast<int>(joint.channels.size());
  return count;
}

absl::Status ValidateSkeleton(const Skeleton& skeleton) {
  const int n = static_cast<int>(skeleton.joints.size());
  if (n == 0) return absl::InvalidArgumentError("joints: the skeleton has no joints");
  for (int i = 0; i < n; ++i) {
    const Joint& joint = skeleton.joints[i];
    // Built only for an error message: this loop runs on every request.
    const auto path = [i] { return absl::StrCat("joints[", i, "]"); };
    if (joint.parent < -1 || joint.parent >= n) {
      return absl::InvalidArgumentError(absl::StrCat(
          path(), ".parent: ", joint.parent, " is out of range (-1 for a root, or 0..", n - 1,
          ")"));
    }
    if (joint.parent >= i) {
      if (ParentChainLoops(skeleton, i)) {
        return absl::InvalidArgumentError(absl::StrCat(
            path(), ".parent: ", joint.parent, " forms a cycle (joint \"", joint.name,
            "\" is its own ancestor)"));
      }
      return absl::InvalidArgumentError(absl::StrCat(
          path(), ".parent: ", joint.parent,
          " must name an earlier joint (joints are listed parents first)"));
    }
    if (!IsFinite(joint.offset)) {
      return absl::InvalidArgumentError(
          absl::StrCat(path(), ".offset: ", Vec3String(joint.offset), " is not finite"));
    }
    for (size_t e = 0; e < joint.end_sites.size(); ++e) {
      if (!IsFinite(joint.end_sites[e])) {
        return absl::InvalidArgumentError(absl::StrCat(path(), ".end_sites[", e, "]: ",
                                                       Vec3String(joint.end_sites[e]),
                                                       " is not finite"));
      }
    }
    if (joint.channels.size() > 6) {
      return absl::InvalidArgumentError(absl::StrCat(
          path(), ".channels: ", joint.channels.size(), " channels, at most 6 allowed"));
    }
    std::array<bool, 6> seen{};
    for (ChannelKind kind : joint.channels) {
      bool& was_seen = seen[static_cast<size_t>(kind)];
      if (was_seen) {
        return absl::InvalidArgumentError(
            absl::StrCat(path(), ".channels: ", std::string(ChannelName(kind)), " appears twice"));
      }
      was_seen = true;
    }
  }
  return absl::OkStatus();
}

}  // namespace koma
