// Fuzz target: any bytes as a per-frame curve CSV (formats/curve_csv.h).
//
// ParseCurveCsv must answer OK or an error status for every input. When it accepts the input,
// the round trip must hold as formats/curve_csv.h promises: WriteCurveCsv of the ids and
// samples reads back to the same ids and values bit for bit (-0 reads back as +0), and
// writing that again gives the same bytes.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/curves.h"
#include "formats/curve_csv.h"
#include "fuzz/fuzz_check.h"

namespace {

constexpr double kFps = 30.0;

// Equal bits, except that -0 and +0 count as the same (the writer prints -0 as "0").
bool SameBits(double a, double b) {
  if (a == 0.0 && b == 0.0) return true;
  uint64_t x = 0;
  uint64_t y = 0;
  std::memcpy(&x, &a, sizeof x);
  std::memcpy(&y, &b, sizeof y);
  return x == y;
}

std::string Write(const koma::CurveSet& set) {
  std::vector<std::string> ids;
  std::vector<std::vector<double>> values;
  for (const koma::Curve& curve : set.curves) {
    ids.push_back(curve.id);
    values.push_back(curve.samples);
  }
  return koma::formats::WriteCurveCsv(ids, values);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const absl::StatusOr<koma::CurveSet> set = koma::formats::ParseCurveCsv(text, kFps);
  if (!set.ok()) {
    KOMA_FUZZ_CHECK(!set.status().message().empty(), "an error must say what is wrong");
    return 0;
  }
  for (const koma::Curve& curve : set->curves) {
    KOMA_FUZZ_CHECK(static_cast<int>(curve.samples.size()) == set->frame_count,
                    "one sample per row");
  }
  const std::string written = Write(*set);
  const absl::StatusOr<koma::CurveSet> reread = koma::formats::ParseCurveCsv(written, kFps);
  KOMA_FUZZ_CHECK(reread.ok(), std::string(reread.status().message()).c_str());
  KOMA_FUZZ_CHECK(reread->frame_count == set->frame_count, "same rows");
  KOMA_FUZZ_CHECK(reread->curves.size() == set->curves.size(), "same columns");
  for (size_t c = 0; c < set->curves.size(); ++c) {
    KOMA_FUZZ_CHECK(reread->curves[c].id == set->curves[c].id, "same ids");
    for (size_t f = 0; f < set->curves[c].samples.size(); ++f) {
      KOMA_FUZZ_CHECK(SameBits(reread->curves[c].samples[f], set->curves[c].samples[f]),
                      "same values, bit for bit");
    }
  }
  KOMA_FUZZ_CHECK(Write(*reread) == written, "writing again, same bytes");
  return 0;
}
