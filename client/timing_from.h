// --timing-from SHEET.xdts|TIMING.csv: a sheet an animator edited, read back
// (formats/sheet_timing.h) and built into the request as a given timing (docs/usage.md,
// "Timing from a sheet").
#ifndef KOMA_CLIENT_TIMING_FROM_H_
#define KOMA_CLIENT_TIMING_FROM_H_

#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "formats/sheet_timing.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// The sheet at `path` ("-": standard input): XDTS when its first line (after a byte order
// mark) is XDTS's identifier or its name ends in .xdts, else koma's --timing CSV. Errors and
// warnings are prefixed with the path ("edit.xdts: track \"pitch\", frame 12: ...").
absl::StatusOr<formats::SheetTiming> ReadTimingFrom(const std::string& path);

// One of koma's tracks a sheet is read for: its name in koma's sheet, its drawings (cells 1
// to `drawings`) and how an error names them ("the clip's source frames 1 to 130").
struct KomaSheetTrack {
  std::string name;
  int drawings = 0;
  std::string what;
  // Its column in a drawing sheet CSV (`drawing` for the first group's, `G_drawing` for a
  // further group G's), and per drawing its tau (source frames): a row's source_frame
  // must be its drawing's within kStatedTauTolerance.
  std::string csv_name;
  std::vector<double> taus;
};

// How far a drawing sheet row's source_frame may be from its drawing's tau, in source frames:
// a spreadsheet saving "as shown" rounds to a few decimals; drawings' taus differ by more.
inline constexpr double kStatedTauTolerance = 0.01;

// The sheet's tracks for koma's `tracks` (matched by name, then order), each as 0-based
// drawings per sheet row (formats::SheetDrawings: a blank holds the drawing before).
// `counted` > 0: the clip's counted frames (`counted_note` says on which grid); more rows are
// INVALID_ARGUMENT naming track, frame and cell, and so are fewer unless `shorter_ok`. The
// sheet's warnings go to `warnings` (nullptr: standard error). Errors start with the path.
// `csv`: the CSV this command reads (kSourceFrameCsv: skeletal's, kDrawingCsv: curves'; kXdts:
// none); another CSV is INVALID_ARGUMENT saying which it is, and so is a drawing sheet CSV
// (a row per output frame) on a grid (`counted_note` not empty).
absl::StatusOr<std::vector<std::vector<int>>> ReadSheetDrawings(
    const std::string& path, const std::vector<KomaSheetTrack>& tracks, int counted,
    bool shorter_ok, const std::string& counted_note, std::vector<std::string>* warnings,
    formats::SheetKind csv = formats::SheetKind::kSourceFrameCsv);

// The clip a skeletal timing is applied to, as far as the client knows it: a decoded clip
// has `frame_count` and `source_fps`; a file the server reads whole (glTF, FBX) has neither
// (0), and the server checks the sheet's range and length (given_timing's errors).
struct SkeletalClipShape {
  int frame_count = 0;
  double source_fps = 0;
  std::optional<double> timing_fps;  // --timing-fps; unset: 24
};

// RetimeSkeletal: the sheet's Cell track for the clip's one track (named `track`: a track of
// that name, else the first; any other is an error) as given_timing.source_frames: cell n is
// source frame n - 1 (koma's skeletal sheets name cells so), a blank holds the frame before.
// With the clip's shape known: cells past its last frame and more rows than its counted
// frames (grid frames, or frames without a grid) are INVALID_ARGUMENT naming track, frame
// and cell. The sheet's warnings are appended to `warnings` (nullptr: written to standard
// error, for a file the server reads, whose summary has only the server's warnings).
absl::Status SetSkeletalTimingFrom(const std::string& path, const std::string& track,
                                   const SkeletalClipShape& clip,
                                   v1::RetimeSkeletalRequest* request,
                                   std::vector<std::string>* warnings);

// The sheet of the clip `input` when `timing_from` names a folder (`koma batch`): the folder's
// NAME.xdts, else NAME.timing.csv (the names `koma batch --xdts` and `--timing` write), NAME
// the clip's file name without its extension; NOT_FOUND naming both when neither is there.
// `timing_from` itself when it names a file.
absl::StatusOr<std::string> TimingFromFor(const std::string& timing_from, const std::string& input);

}  // namespace koma::client

#endif  // KOMA_CLIENT_TIMING_FROM_H_
