// Fuzz target: any bytes as a glTF file (formats/gltf.h).
//
// ReadGltf must answer OK or an error status for every input, never crash, hang or trip a
// sanitizer. When it accepts the input: writing it back with nothing replaced reads back to
// the same JSON and buffers; and replacing every animation with two STEP keys of its own
// evaluated values (what a retiming writes) reads back with those keys.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/gltf_animation.h"
#include "formats/gltf.h"
#include "fuzz/fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  koma::formats::GltfReadLimits limits;
  limits.max_nodes = 4096;
  limits.max_keys = 1 << 20;
  limits.max_animations = 256;
  const absl::StatusOr<koma::formats::GltfDocument> document = koma::formats::ReadGltf(bytes, limits);
  if (!document.ok()) {
    KOMA_FUZZ_CHECK(!document.status().message().empty(), "an error must say what is wrong");
    return 0;
  }
  const absl::StatusOr<std::string> same = koma::formats::WriteGltf(*document, {}, false);
  if (!same.ok()) return 0;  // JSON nlohmann cannot write back (invalid UTF-8): an error
  const absl::StatusOr<koma::formats::GltfDocument> reread = koma::formats::ReadGltf(*same, limits);
  KOMA_FUZZ_CHECK(reread.ok(), std::string(reread.status().message()).c_str());
  KOMA_FUZZ_CHECK(reread->json == document->json, "unchanged JSON reads back the same");
  KOMA_FUZZ_CHECK(reread->buffers == document->buffers, "unchanged buffers read back the same");

  std::vector<koma::formats::GltfAnimationKeys> all;
  for (size_t a = 0; a < document->animations.size(); ++a) {
    const koma::GltfClip& clip = document->animations[a].clip;
    koma::formats::GltfAnimationKeys keys;
    keys.animation = static_cast<int>(a);
    keys.times = {koma::GltfClipStart(clip), koma::GltfClipEnd(clip) + 1};
    for (const koma::GltfChannel& channel : clip.channels) {
      const koma::GltfSampler& sampler = clip.samplers[static_cast<size_t>(channel.sampler)];
      std::vector<double> values(2 * static_cast<size_t>(sampler.width));
      for (size_t k = 0; k < 2; ++k) {
        koma::EvaluateGltfSampler(sampler, channel.path == koma::GltfPath::kRotation,
                                  keys.times[0], 0, values.data() + k * sampler.width);
      }
      keys.values.push_back(values);
    }
    all.push_back(keys);
  }
  const absl::StatusOr<std::string> retimed = koma::formats::WriteGltf(*document, all, false);
  if (!retimed.ok()) return 0;
  const absl::StatusOr<koma::formats::GltfDocument> back = koma::formats::ReadGltf(retimed.value(), limits);
  KOMA_FUZZ_CHECK(back.ok(), std::string(back.status().message()).c_str());
  KOMA_FUZZ_CHECK(back->animations.size() == document->animations.size(), "same animations");
  return 0;
}
