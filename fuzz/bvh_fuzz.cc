// Fuzz target: any bytes as a BVH file (formats/bvh.h).
//
// ParseBvh must answer OK or an error status for every input, never crash, hang or trip a
// sanitizer. When it accepts the input, the reader -> writer round trip must hold as
// formats/bvh.h promises: WriteBvh's text reads back to the same clip (every number equal,
// -0 == +0) and writing that again gives the same bytes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/skeleton.h"
#include "formats/bvh.h"
#include "fuzz/fuzz_check.h"

namespace {

bool SameVec3(const koma::Vec3& a, const koma::Vec3& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

bool SameClip(const koma::SkeletalClip& a, const koma::SkeletalClip& b) {
  if (a.frame_time != b.frame_time || a.frame_count != b.frame_count || a.values != b.values ||
      a.skeleton.joints.size() != b.skeleton.joints.size()) {
    return false;
  }
  for (size_t j = 0; j < a.skeleton.joints.size(); ++j) {
    const koma::Joint& x = a.skeleton.joints[j];
    const koma::Joint& y = b.skeleton.joints[j];
    if (x.name != y.name || x.parent != y.parent || !SameVec3(x.offset, y.offset) ||
        x.channels != y.channels || x.end_sites.size() != y.end_sites.size()) {
      return false;
    }
    for (size_t e = 0; e < x.end_sites.size(); ++e) {
      if (!SameVec3(x.end_sites[e], y.end_sites[e])) return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const absl::StatusOr<koma::SkeletalClip> clip = koma::formats::ParseBvh(text);
  if (!clip.ok()) {
    KOMA_FUZZ_CHECK(!clip.status().message().empty(), "an error must say what is wrong");
    return 0;
  }
  KOMA_FUZZ_CHECK(koma::ValidateSkeleton(clip->skeleton).ok(), "ParseBvh's result validates");
  const std::string written = koma::formats::WriteBvh(*clip);
  const absl::StatusOr<koma::SkeletalClip> reread = koma::formats::ParseBvh(written);
  KOMA_FUZZ_CHECK(reread.ok(), std::string(reread.status().message()).c_str());
  KOMA_FUZZ_CHECK(SameClip(*clip, *reread), "WriteBvh's text reads back to the same clip");
  KOMA_FUZZ_CHECK(koma::formats::WriteBvh(*reread) == written, "writing again, same bytes");
  return 0;
}
