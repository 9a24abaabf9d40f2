// Curve files for `koma curves` and `koma lipblink`: motion3.json or per-frame CSV in, the
// same (or CSV) out with some curves replaced. "-" is standard input / output.
#ifndef KOMA_CLIENT_CURVE_FILES_H_
#define KOMA_CLIENT_CURVE_FILES_H_

#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "client/call_flags.h"
#include "convert/curve_text.h"
#include "core/curves.h"

namespace koma::client {

// The two curve file formats; kAuto: from the name, else the contents (see ReadCurveInput).
enum class CurveFormat { kAuto, kMotion3, kCsv };

// "motion3" -> kMotion3, "csv" -> kCsv, "" or "auto" -> kAuto (the --format values).
CurveFormat CurveFormatFromFlag(const std::string& value);

// True for "*.csv" (any case).
bool IsCsvPath(const std::string& path);

// False (with the reason on stderr) when `output` asks for motion3.json but `input` is a
// CSV, which has no motion3 document to write back. Kept for callers that decide by names
// only; the commands use CurveOutputFormat.
bool CanWriteOutput(const std::string& input, const std::string& output);

// The parsed file (convert/curve_text.h) and the format it was read as.
struct CurveInput : convert::CurveInput {
  CurveFormat format = CurveFormat::kMotion3;  // what was read: kMotion3 or kCsv
  std::string text;                            // the file as read (for --send-file)
};

// A motion3.json, a Spine skeleton JSON (formats::IsSpineJson; only for `command` "curves":
// `spine` set, no animation selected yet, see client/spine_curves.h), or a CSV (`frame,<id>,...`)
// at `csv_fps` frames per second. A *.skel (binary Spine) is refused as such. The format:
// `format` when not kAuto; else a text that starts with "{" is motion3.json, one that starts
// with a "frame" header is CSV, else the name decides (*.csv is CSV, anything else
// motion3.json). A BVH file is refused as such ("x.bvh is a BVH file, ..."), naming
// `command`. Errors name the file ("standard input" for "-").
// The `command` under which ReadCurveInput also reads a Spine skeleton for `koma lipblink`
// (client/spine_lip_blink.h); plain "lipblink" refuses one, pointing at the Spine flags.
inline constexpr char kLipBlinkSpineCommand[] = "lipblink --animation";

absl::StatusOr<CurveInput> ReadCurveInput(const std::string& path, double csv_fps,
                                          CurveFormat format, absl::string_view command);

// The format `path` is written in: `format` when not kAuto, else *.csv is CSV, "-" the
// input's format and any other name motion3.json. INVALID_ARGUMENT naming the flag when that
// is motion3.json and the input was CSV (no motion3 document to write back), or when the
// name ends in .bvh.
absl::StatusOr<CurveFormat> CurveOutputFormat(const std::string& path, CurveFormat format,
                                              const CurveInput& input);

// The flags `koma curves` and `koma lipblink` share (client/command_flags.h registers them),
// extended by each command's own.
struct CurveFileArgs : CallFlags {
  std::string input;                 // .motion3.json or .csv; "-": standard input
  std::string output;                // .motion3.json (needs a motion3 input) or .csv; "-"
  std::string report;                // --report: HTML report to write; empty: none
  std::string xdts;                  // --xdts: XDTS exposure sheet to write; empty: none
  double csv_fps = 30.0;             // --fps, frames per second of a CSV input
  std::optional<double> timing_fps;  // --timing-fps: the film grid; unset: the server's 24
  std::string format;                // --format motion3|csv: of the output "-"
  bool send_file = false;  // --send-file: the file's text (motion3_json or csv_text + csv_fps)
  std::string timing_from;  // --timing-from: an edited XDTS to apply; empty: none
};

// --send-file: `request` (RetimeCurvesRequest or LipBlinkRequest) carries the file as read
// for the server to parse, in place of its decoded curves: csv_text with csv_fps = --fps for
// a CSV, else motion3_json.
template <typename Request>
void PutCurveFile(const CurveFileArgs& args, const CurveInput& input, Request* request) {
  request->clear_curves();
  if (input.format == CurveFormat::kCsv) {
    request->set_csv_text(input.text);
    request->set_csv_fps(args.csv_fps);
  } else {
    request->set_motion3_json(input.text);
  }
}

using convert::CurveReplacement;  // a retimed curve (convert/curve_text.h)

// Writes `input` with replacements[i] (when set) in place of curve i: as CSV (every curve,
// the others sampled at every frame), else as motion3.json (needs a motion3 input; the
// others untouched, Meta counts recomputed). The format as CurveOutputFormat(path, format).
absl::Status WriteCurveOutput(const std::string& path, const CurveInput& input,
                              const std::vector<std::optional<CurveReplacement>>& replacements,
                              CurveFormat format = CurveFormat::kAuto);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CURVE_FILES_H_
