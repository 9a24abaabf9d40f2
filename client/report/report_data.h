// Shared pieces of the reports' data: rounded numbers, plots thinned to what a screen shows,
// and the compact encoding of the player's joint positions.
#ifndef KOMA_CLIENT_REPORT_REPORT_DATA_H_
#define KOMA_CLIENT_REPORT_REPORT_DATA_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/types/span.h"
#include "formats/xdts.h"
#include "nlohmann/json.hpp"

namespace koma::client::report {

// Points a plot keeps at most: a line plot is at most ~1000 px wide, two points (the lowest
// and highest) per pixel column keep every peak.
inline constexpr int kMaxPlotPoints = 2000;

// `value` to 6 significant digits (what a plot can show), through printf's %.6g: the same
// bits on every machine. Non-finite values become 0.
double Round6(double value);

// A plot of values[i] at x = i * dx: {"x": [...], "y": [...]}. With more than
// kMaxPlotPoints values, each of kMaxPlotPoints / 2 buckets of consecutive values keeps its
// lowest and its highest value, in their order (a peak is never lost).
nlohmann::json ThinnedPlot(absl::Span<const double> values, double dx);

// Runs of equal consecutive values: [[first index, length, value], ...].
nlohmann::json Runs(absl::Span<const int> values);

// The player's positions: `values` (frames x per_frame) quantised to multiples of `step`
// (rounded), each value minus the same value of the previous frame (the first frame: minus
// 0), zigzag-coded, written as little-endian base-128 varints, then base64. Smooth motion
// changes little from one frame to the next, so most values take one byte. report.js's
// unpackPositions reverses it. Values beyond +-2^52 steps are clamped.
std::string PackQuantised(absl::Span<const double> values, int per_frame, double step);

// The exposure sheet `--xdts` writes (client/xdts_sheets.h), for the page's "Exposure sheet
// (XDTS)" section: {"name", "rows", "tracks": [{"name", "changes": [[row, cell], ...]}],
// "dialog": [{"name", "lines": [[begin, end, speaker, text], ...]}]}, a cell listed where it
// changes ("" empty), as the file has it; {"error": message} when the answer has no sheet.
nlohmann::json ExposureSheetData(const absl::StatusOr<formats::XdtsSheet>& sheet);

// RFC 4648 base64 with padding.
std::string Base64(const std::string& bytes);

}  // namespace koma::client::report

#endif  // KOMA_CLIENT_REPORT_REPORT_DATA_H_
