// Fuzz target: any bytes as a Spine skeleton JSON file (formats/spine.h).
//
// ParseSpine must answer OK or an error status for every input (deep nesting is refused before
// nlohmann recurses). When it accepts the input, the reader -> writer round trip must hold:
// writing with no replacement gives JSON equal to the input's; writing with every curve of
// every other animation with bone keys replaced by two stepped keys (frames 0 and 1) succeeds,
// parses again with the same animations, the replaced curves read back as those keys, the other
// animations' curves read back unchanged, and writing the re-read file with no replacement
// gives the same bytes.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/curves.h"
#include "formats/spine.h"
#include "fuzz/fuzz_check.h"

namespace {

bool SamePoint(const koma::CurvePoint& a, const koma::CurvePoint& b) {
  return a.frame == b.frame && a.value == b.value;
}

bool SameCurve(const koma::Curve& a, const koma::Curve& b) {
  if (a.id != b.id || !SamePoint(a.start, b.start) || a.segments.size() != b.segments.size()) {
    return false;
  }
  for (size_t s = 0; s < a.segments.size(); ++s) {
    const koma::CurveSegment& x = a.segments[s];
    const koma::CurveSegment& y = b.segments[s];
    if (x.type != y.type || !SamePoint(x.end, y.end)) return false;
    if (x.type == koma::SegmentType::kBezier &&
        (!SamePoint(x.handles[0], y.handles[0]) || !SamePoint(x.handles[1], y.handles[1]))) {
      return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const absl::StatusOr<koma::formats::SpineFile> file = koma::formats::ParseSpine(text);
  if (!file.ok()) {
    KOMA_FUZZ_CHECK(!file.status().message().empty(), "an error must say what is wrong");
    return 0;
  }
  const absl::StatusOr<std::string> same = koma::formats::WriteSpine(*file, {});
  KOMA_FUZZ_CHECK(same.ok(), std::string(same.status().message()).c_str());
  KOMA_FUZZ_CHECK(nlohmann::ordered_json::parse(*same) == file->document,
                  "no replacement writes the same JSON");

  // Every curve of every other animation with bone keys: two stepped keys at frames 0 and 1.
  std::vector<koma::formats::SpineRetimed> retimed;
  std::vector<bool> replaced(file->animations.size(), false);
  bool take = true;
  for (size_t a = 0; a < file->animations.size(); ++a) {
    const koma::formats::SpineAnimation& animation = file->animations[a];
    if (animation.curves.curves.empty()) continue;
    take = !take;
    if (take) continue;
    koma::formats::SpineRetimed one{static_cast<int>(a), {}};
    for (const koma::Curve& curve : animation.curves.curves) {
      one.stepped.push_back(std::vector<koma::CurvePoint>{
          {0.0, curve.start.value}, {1.0, koma::EvaluateCurve(curve, 1e9, false)}});
    }
    replaced[a] = true;
    retimed.push_back(std::move(one));
  }
  const absl::StatusOr<std::string> written = koma::formats::WriteSpine(*file, retimed);
  KOMA_FUZZ_CHECK(written.ok(), std::string(written.status().message()).c_str());
  const absl::StatusOr<koma::formats::SpineFile> reread = koma::formats::ParseSpine(*written);
  KOMA_FUZZ_CHECK(reread.ok(), std::string(reread.status().message()).c_str());
  KOMA_FUZZ_CHECK(reread->animations.size() == file->animations.size(), "same animations");
  KOMA_FUZZ_CHECK(reread->version == file->version, "written in the same version");
  for (size_t a = 0; a < file->animations.size(); ++a) {
    const std::vector<koma::Curve>& before = file->animations[a].curves.curves;
    const std::vector<koma::Curve>& after = reread->animations[a].curves.curves;
    KOMA_FUZZ_CHECK(reread->animations[a].name == file->animations[a].name, "same names");
    KOMA_FUZZ_CHECK(after.size() == before.size(), "same curves");
    for (size_t c = 0; c < before.size(); ++c) {
      if (!replaced[a]) {
        KOMA_FUZZ_CHECK(SameCurve(after[c], before[c]), "an untouched curve reads back unchanged");
        continue;
      }
      KOMA_FUZZ_CHECK(after[c].id == before[c].id, "a replaced curve keeps its id");
      KOMA_FUZZ_CHECK(koma::EvaluateCurve(after[c], 0.0, false) == before[c].start.value,
                      "first stepped key");
      KOMA_FUZZ_CHECK(koma::EvaluateCurve(after[c], 1.0, false) ==
                          koma::EvaluateCurve(before[c], 1e9, false),
                      "second stepped key");
    }
  }
  const absl::StatusOr<std::string> again = koma::formats::WriteSpine(*reread, {});
  KOMA_FUZZ_CHECK(again.ok(), std::string(again.status().message()).c_str());
  KOMA_FUZZ_CHECK(*again == *written, "writing the re-read file gives the same bytes");
  return 0;
}
