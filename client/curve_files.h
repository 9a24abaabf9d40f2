// Curve files for `koma curves` and `koma lipblink`: motion3.json or per-frame CSV in, the
// same (or CSV) out with some curves replaced.
#ifndef KOMA_CLIENT_CURVE_FILES_H_
#define KOMA_CLIENT_CURVE_FILES_H_

#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "convert/curve_text.h"
#include "core/curves.h"

namespace koma::client {

// True for "*.csv" (any case).
bool IsCsvPath(const std::string& path);

// False (with the reason on stderr) when `output` asks for motion3.json but `input` is a
// CSV, which has no motion3 document to write back.
bool CanWriteOutput(const std::string& input, const std::string& output);

using convert::CurveInput;  // the parsed file (convert/curve_text.h)

// A motion3.json, or a CSV (`frame,<id>,...`) at `csv_fps` frames per second. Errors name
// the file.
absl::StatusOr<CurveInput> ReadCurveInput(const std::string& path, double csv_fps);

using convert::CurveReplacement;  // a retimed curve (convert/curve_text.h)

// Writes `input` with replacements[i] (when set) in place of curve i: as CSV (every curve,
// the others sampled at every frame) when `path` ends in .csv, else as motion3.json (needs a
// motion3 input; the others untouched, Meta counts recomputed).
absl::Status WriteCurveOutput(const std::string& path, const CurveInput& input,
                              const std::vector<std::optional<CurveReplacement>>& replacements);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CURVE_FILES_H_
