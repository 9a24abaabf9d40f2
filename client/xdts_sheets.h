// Each RPC's answer as an XDTS exposure sheet (formats/xdts.h; the mapping is in
// docs/formats.md, "XDTS exposure sheet"): one sheet row per frame of the film grid (per
// source frame when timing_fps is 0), drawings numbered 1, 2, 3 ... per Cell track.
// python/koma/_xdts.py builds the same sheets, byte for byte (tests/e2e/xdts_e2e_test.sh).
#ifndef KOMA_CLIENT_XDTS_SHEETS_H_
#define KOMA_CLIENT_XDTS_SHEETS_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "formats/xdts.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// The name of a clip's sheet and layers: the file name without its folder and its extension
// (.bvh, .motion3.json, .csv, .json, .glb, .gltf, .vrm, .vrma, and a voice's .wav, .flac,
// .ogg, .oga, .opus, .mp3, .tsv); for standard input ("-") `fallback`'s, and "koma" when that
// is "-" or empty too.
std::string XdtsClipName(const std::string& input, const std::string& fallback);

// RetimeSkeletal: one Cell track named `name`. Rows: with a grid, the grid frames of the
// retimed sequence (0 .. the last output frame's grid frame), each showing the drawing of its
// output frames (a grid frame no output frame shows, a source slower than the grid, repeats
// the row before: what the output shows then); without one, the output frames. Each cell is
// the source frame the row shows, counted from 1 (cell "1" is the clip's first frame).
absl::StatusOr<formats::XdtsSheet> SkeletalXdtsSheet(const v1::RetimeSkeletalResponse& response,
                                                     const std::string& name);

// RetimeCurves: one Cell track per DrawingTiming that times at least one curve (the curves
// that share a timing are one layer of drawings), named "NAME (on N)" when there is one such
// track, else "ID, ID, ... (on N)" by its curves. Rows: grid frames 0 .. the last drawing's
// start (the clip's last grid frame), or the source frames; cell = drawing index + 1.
absl::StatusOr<formats::XdtsSheet> CurvesXdtsSheet(const v1::RetimeCurvesResponse& response,
                                                   const std::string& name);

// LipBlink: Cell tracks for the mouths (cells 1 closed, 2 mid, 3 open) then the eyes (1 open,
// 2 half, 3 closed), one per group of curves with the same cells, named "ID, ... (1 closed, 2
// mid, 3 open)"; a Dialog track per group of mouths with the same speech intervals, a line
// [NAME, "speech K"] per interval. Rows: the grid frames of a clip of the converted curves'
// length at `source_fps`, or its frames. A row inside a mouth hold shows the hold's shape,
// inside a blink's repaint its drawing (docs/semantics.md, LipBlink); elsewhere the curve keeps
// its input, and the row shows the level nearest the converted value at the source frame
// nearest the row's time (ties to the first of closed, mid, open).
absl::StatusOr<formats::XdtsSheet> LipBlinkXdtsSheet(const v1::LipBlinkResponse& response,
                                                     double source_fps, const std::string& name);

// Eye drawings (0 open, 1 half, 2 closed) an eye's blinks repaint, over `rows` rows; -1
// elsewhere. The repaint of docs/semantics.md (core/lip_blink_eyes.cc, Paint): the closing
// phase open, closed from C_start through max(C_end, C_start + k - 1), half for k frames, open
// to the end of the opening span (or of the half-open frames when later), never into the next
// blink.
std::vector<int> BlinkRows(const v1::EyeTrack& eye, int rows);

}  // namespace koma::client

#endif  // KOMA_CLIENT_XDTS_SHEETS_H_
