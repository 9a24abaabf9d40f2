// WriteBvh: the hierarchy depth-first with an explicit stack (a long joint chain cannot overflow
// the call stack), then one line of values per frame in the same joint order.
#include <cassert>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "formats/bvh.h"
#include "formats/number_format.h"

namespace koma::formats {
namespace {

void AppendLine(std::string* out, int depth, std::string_view text) {
  out->append(static_cast<size_t>(depth), '\t');
  out->append(text);
  out->push_back('\n');
}

void AppendOffset(std::string* out, int depth, const Vec3& offset) {
  AppendLine(out, depth,
             absl::StrCat("OFFSET ", FormatDouble(offset.x), " ", FormatDouble(offset.y), " ",
                          FormatDouble(offset.z)));
}

// "ROOT"/"JOINT" line, "{", OFFSET and CHANNELS lines of `joint` at `depth`.
void AppendJointHead(std::string* out, int depth, const Joint& joint) {
  AppendLine(out, depth, absl::StrCat(joint.parent < 0 ? "ROOT " : "JOINT ", joint.name));
  AppendLine(out, depth, "{");
  AppendOffset(out, depth + 1, joint.offset);
  std::string channels = absl::StrCat("CHANNELS ", joint.channels.size());
  for (ChannelKind kind : joint.channels) channels.append(" ").append(ChannelName(kind));
  AppendLine(out, depth + 1, channels);
}

// The End Sites of `joint` and its closing brace.
void AppendJointTail(std::string* out, int depth, const Joint& joint) {
  for (const Vec3& end_site : joint.end_sites) {
    AppendLine(out, depth + 1, "End Site");
    AppendLine(out, depth + 1, "{");
    AppendOffset(out, depth + 2, end_site);
    AppendLine(out, depth + 1, "}");
  }
  AppendLine(out, depth, "}");
}

// Writes the HIERARCHY section and returns the joints in the order written (depth-first).
std::vector<int> AppendHierarchy(std::string* out, const Skeleton& skeleton) {
  const int n = static_cast<int>(skeleton.joints.size());
  std::vector<std::vector<int>> children(n);
  std::vector<int> roots;
  for (int j = 0; j < n; ++j) {
    const int parent = skeleton.joints[j].parent;
    (parent < 0 ? roots : children[parent]).push_back(j);
  }
  struct Open {
    int joint;
    size_t next_child;
  };
  std::vector<int> order;
  order.reserve(n);
  out->append("HIERARCHY\n");
  for (int root : roots) {
    std::vector<Open> stack = {{root, 0}};
    order.push_back(root);
    AppendJointHead(out, 0, skeleton.joints[root]);
    while (!stack.empty()) {
      Open& top = stack.back();
      const int depth = static_cast<int>(stack.size()) - 1;
      if (top.next_child < children[top.joint].size()) {
        const int child = children[top.joint][top.next_child++];
        order.push_back(child);
        AppendJointHead(out, depth + 1, skeleton.joints[child]);
        stack.push_back({child, 0});  // invalidates `top`, which is not used again
      } else {
        AppendJointTail(out, depth, skeleton.joints[top.joint]);
        stack.pop_back();
      }
    }
  }
  return order;
}

// Writes the MOTION section with each frame's values in joint `order`.
void AppendMotion(std::string* out, const SkeletalClip& clip, const std::vector<int>& order) {
  const std::vector<Joint>& joints = clip.skeleton.joints;
  std::vector<size_t> first_channel(joints.size());  // index of the joint's first value
  size_t channels = 0;
  for (size_t j = 0; j < joints.size(); ++j) {
    first_channel[j] = channels;
    channels += joints[j].channels.size();
  }
  absl::StrAppend(out, "MOTION\nFrames: ", clip.frame_count,
                  "\nFrame Time: ", FormatDouble(clip.frame_time), "\n");
  for (size_t frame = 0; frame < static_cast<size_t>(clip.frame_count); ++frame) {
    const double* values = clip.values.data() + frame * channels;
    bool first = true;
    for (int j : order) {
      for (size_t c = 0; c < joints[j].channels.size(); ++c) {
        if (!first) out->push_back(' ');
        first = false;
        out->append(FormatDouble(values[first_channel[j] + c]));
      }
    }
    out->push_back('\n');
  }
}

}  // namespace

std::string WriteBvh(const SkeletalClip& clip) {
  assert(ValidateSkeleton(clip.skeleton).ok());
  assert(clip.frame_count >= 0);
  assert(clip.values.size() == static_cast<size_t>(clip.frame_count) * ChannelCount(clip.skeleton));
  std::string out;
  const std::vector<int> order = AppendHierarchy(&out, clip.skeleton);
  AppendMotion(&out, clip, order);
  return out;
}

}  // namespace koma::formats
