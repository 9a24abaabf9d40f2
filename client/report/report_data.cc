#include "client/report/report_data.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "absl/strings/str_format.h"

namespace koma::client::report {

double Round6(double value) {
  if (!std::isfinite(value)) return 0.0;
  return std::strtod(absl::StrFormat("%.6g", value).c_str(), nullptr);
}

nlohmann::json ThinnedPlot(absl::Span<const double> values, double dx) {
  nlohmann::json x = nlohmann::json::array();
  nlohmann::json y = nlohmann::json::array();
  const size_t n = values.size();
  auto add = [&](size_t i) {
    x.push_back(Round6(static_cast<double>(i) * dx));
    y.push_back(Round6(values[i]));
  };
  if (n <= static_cast<size_t>(kMaxPlotPoints)) {
    for (size_t i = 0; i < n; ++i) add(i);
  } else {
    const size_t buckets = kMaxPlotPoints / 2;
    for (size_t b = 0; b < buckets; ++b) {
      const size_t begin = b * n / buckets;
      const size_t end = (b + 1) * n / buckets;
      size_t low = begin;
      size_t high = begin;
      for (size_t i = begin; i < end; ++i) {
        if (values[i] < values[low]) low = i;
        if (values[i] > values[high]) high = i;
      }
      add(std::min(low, high));
      if (low != high) add(std::max(low, high));
    }
  }
  return {{"x", std::move(x)}, {"y", std::move(y)}};
}

nlohmann::json Runs(absl::Span<const int> values) {
  nlohmann::json runs = nlohmann::json::array();
  size_t i = 0;
  while (i < values.size()) {
    size_t j = i + 1;
    while (j < values.size() && values[j] == values[i]) ++j;
    runs.push_back({i, j - i, values[i]});
    i = j;
  }
  return runs;
}

std::string PackQuantised(absl::Span<const double> values, int per_frame, double step) {
  constexpr double kLimit = 4503599627370496.0;  // 2^52: exact in a double and in JavaScript
  std::string bytes;
  bytes.reserve(values.size() + values.size() / 4);
  std::vector<int64_t> previous(per_frame, 0);
  for (size_t i = 0; i < values.size(); ++i) {
    const double scaled = std::isfinite(values[i]) ? std::round(values[i] / step) : 0.0;
    const int64_t q = static_cast<int64_t>(std::clamp(scaled, -kLimit, kLimit));
    int64_t& last = previous[i % per_frame];
    const int64_t delta = q - last;
    last = q;
    uint64_t zigzag =
        delta >= 0 ? static_cast<uint64_t>(delta) * 2 : static_cast<uint64_t>(-(delta + 1)) * 2 + 1;
    while (zigzag >= 0x80) {
      bytes.push_back(static_cast<char>((zigzag & 0x7f) | 0x80));
      zigzag >>= 7;
    }
    bytes.push_back(static_cast<char>(zigzag));
  }
  return Base64(bytes);
}

std::string Base64(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (static_cast<uint8_t>(bytes[i]) << 16) |
                       (static_cast<uint8_t>(bytes[i + 1]) << 8) |
                       static_cast<uint8_t>(bytes[i + 2]);
    out.push_back(kAlphabet[v >> 18]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(kAlphabet[(v >> 6) & 63]);
    out.push_back(kAlphabet[v & 63]);
  }
  if (i < bytes.size()) {
    uint32_t v = static_cast<uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<uint8_t>(bytes[i + 1]) << 8;
    out.push_back(kAlphabet[v >> 18]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

nlohmann::json ExposureSheetData(const absl::StatusOr<formats::XdtsSheet>& sheet) {
  if (!sheet.ok()) return {{"error", std::string(sheet.status().message())}};
  nlohmann::json tracks = nlohmann::json::array();
  for (const formats::XdtsCellTrack& track : sheet->cell_tracks) {
    nlohmann::json changes = nlohmann::json::array();
    for (size_t r = 0; r < track.cells.size(); ++r) {
      if (r == 0 || track.cells[r] != track.cells[r - 1]) {
        changes.push_back({static_cast<int>(r), track.cells[r]});
      }
    }
    tracks.push_back({{"name", track.name}, {"changes", std::move(changes)}});
  }
  nlohmann::json dialog = nlohmann::json::array();
  for (const formats::XdtsDialogTrack& track : sheet->dialog_tracks) {
    nlohmann::json lines = nlohmann::json::array();
    for (const formats::XdtsDialogLine& line : track.lines) {
      lines.push_back({line.begin, line.end, line.speaker, line.text});
    }
    dialog.push_back({{"name", track.name}, {"lines", std::move(lines)}});
  }
  return {{"name", sheet->name}, {"rows", sheet->duration}, {"tracks", std::move(tracks)},
          {"dialog", std::move(dialog)}};
}

}  // namespace koma::client::report
