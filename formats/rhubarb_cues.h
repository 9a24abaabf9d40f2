// Rhubarb Lip Sync's mouth cues as text (docs/formats.md, "Mouth cues"), read and written:
//
//   JSON (`rhubarb -f json`):               TSV (`rhubarb -f tsv`):
//     {"metadata": {"soundFile": "v.wav",     0.00	X
//                   "duration": 1.25},        0.05	D
//      "mouthCues": [                         0.27	C
//        {"start": 0.00, "end": 0.05,         1.25	X
//         "value": "X"}, ...]}
//
// A TSV line is a cue's start time (seconds) and letter; each cue ends where the next line
// starts, and the last line (Rhubarb's closing X) has no end. Letters are A-H and X.
#ifndef KOMA_FORMATS_RHUBARB_CUES_H_
#define KOMA_FORMATS_RHUBARB_CUES_H_

#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "core/mouth_cues.h"

namespace koma::formats {

// JSON when the text starts with '{' (after whitespace and a UTF-8 byte order mark), else
// TSV. INVALID_ARGUMENT naming the JSON path ("mouthCues[3].value: \"Q\" is not one of
// A-H, X") or the TSV line ("line 4: ..."), for malformed JSON or lines, a missing or mistyped
// field, a time that is not a finite number >= 0, an end not after its start, cues out of
// order or overlapping, no cues. The last TSV cue ends at +infinity.
absl::StatusOr<std::vector<MouthCue>> ParseRhubarbCues(std::string_view text);

// Rhubarb's layout, times as the shortest decimal of frame / fps (formats/number_format.h).
std::string WriteRhubarbJson(const std::vector<MouthCue>& cues, double duration_s,
                             std::string_view sound_file);
// One line per cue start, then the last cue's end with X.
std::string WriteRhubarbTsv(const std::vector<MouthCue>& cues);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_RHUBARB_CUES_H_
