// Fuzz target: any bytes as a Live2D motion3.json file (formats/motion3.h).
//
// ParseMotion3 must answer OK or an error status for every input (nesting included: deep
// arrays are refused before nlohmann recurses). When it accepts the input, the reader ->
// writer round trip must hold: WriteMotion3 with every odd-numbered curve replaced by stepped
// keys succeeds, its text parses again, the untouched curves read back unchanged, the replaced
// ones read back as those stepped keys, Meta's counts are CountMotion3's, and writing the
// re-read file with no replacement gives the same bytes.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/curves.h"
#include "formats/motion3.h"
#include "fuzz/fuzz_check.h"

namespace {

using Replacements = std::vector<std::optional<std::vector<koma::CurvePoint>>>;

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

int MetaInt(const nlohmann::ordered_json& meta, const char* key) {
  const auto found = meta.find(key);
  if (found == meta.end() || !found->is_number_integer()) return -1;
  return found->get<int>();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const absl::StatusOr<koma::formats::Motion3File> file = koma::formats::ParseMotion3(text);
  if (!file.ok()) {
    KOMA_FUZZ_CHECK(!file.status().message().empty(), "an error must say what is wrong");
    return 0;
  }
  const std::vector<koma::Curve>& curves = file->curves.curves;
  KOMA_FUZZ_CHECK(file->targets.size() == curves.size(), "a target per curve");

  // Odd curves become two stepped keys at frames 0 and 1: their first and last values.
  Replacements stepped(curves.size());
  for (size_t c = 1; c < curves.size(); c += 2) {
    const double last = curves[c].segments.back().end.value;
    stepped[c] = std::vector<koma::CurvePoint>{{0.0, curves[c].start.value}, {1.0, last}};
  }
  const absl::StatusOr<std::string> written = koma::formats::WriteMotion3(*file, stepped);
  KOMA_FUZZ_CHECK(written.ok(), std::string(written.status().message()).c_str());

  const absl::StatusOr<koma::formats::Motion3File> reread = koma::formats::ParseMotion3(*written);
  KOMA_FUZZ_CHECK(reread.ok(), std::string(reread.status().message()).c_str());
  KOMA_FUZZ_CHECK(reread->curves.curves.size() == curves.size(), "same number of curves");
  KOMA_FUZZ_CHECK(reread->curves.fps == file->curves.fps, "same fps");
  KOMA_FUZZ_CHECK(reread->curves.frame_count == file->curves.frame_count, "same frame count");
  for (size_t c = 0; c < curves.size(); ++c) {
    const koma::Curve& back = reread->curves.curves[c];
    if (!stepped[c].has_value()) {
      KOMA_FUZZ_CHECK(SameCurve(back, curves[c]), "an untouched curve reads back unchanged");
      continue;
    }
    KOMA_FUZZ_CHECK(back.id == curves[c].id, "a replaced curve keeps its id");
    KOMA_FUZZ_CHECK(back.segments.size() == 1, "one stepped segment");
    KOMA_FUZZ_CHECK(back.segments[0].type == koma::SegmentType::kStepped, "stepped");
    KOMA_FUZZ_CHECK(SamePoint(back.start, (*stepped[c])[0]), "first stepped key");
    KOMA_FUZZ_CHECK(SamePoint(back.segments[0].end, (*stepped[c])[1]), "second stepped key");
  }

  const absl::StatusOr<koma::formats::Motion3Counts> counts =
      koma::formats::CountMotion3(reread->document);
  KOMA_FUZZ_CHECK(counts.ok(), "the written document counts");
  const nlohmann::ordered_json& meta = reread->document["Meta"];
  KOMA_FUZZ_CHECK(MetaInt(meta, "CurveCount") == counts->curve_count, "Meta.CurveCount");
  KOMA_FUZZ_CHECK(MetaInt(meta, "TotalSegmentCount") == counts->total_segment_count,
                  "Meta.TotalSegmentCount");
  KOMA_FUZZ_CHECK(MetaInt(meta, "TotalPointCount") == counts->total_point_count,
                  "Meta.TotalPointCount");
  KOMA_FUZZ_CHECK(MetaInt(meta, "UserDataCount") == counts->user_data_count, "Meta.UserDataCount");
  KOMA_FUZZ_CHECK(MetaInt(meta, "TotalUserDataSize") == counts->total_user_data_size,
                  "Meta.TotalUserDataSize");

  const absl::StatusOr<std::string> again =
      koma::formats::WriteMotion3(*reread, Replacements(curves.size()));
  KOMA_FUZZ_CHECK(again.ok(), std::string(again.status().message()).c_str());
  KOMA_FUZZ_CHECK(*again == *written, "writing the re-read file gives the same bytes");
  return 0;
}
