// `koma batch` inputs: files, folders (searched recursively by extension) and @lists, each
// mapped to its output path under the output folder.
#ifndef KOMA_CLIENT_BATCH_BATCH_INPUTS_H_
#define KOMA_CLIENT_BATCH_BATCH_INPUTS_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace koma::client::batch {

// One clip of the batch.
struct BatchItem {
  std::string input;     // as found: a path the process can open
  std::string relative;  // its output's path below the output folder ("a/b.bvh")
  std::string output;    // out_dir / relative
  std::string timing;    // the timing sheet beside the output; empty when none is asked for
  std::string report;    // the HTML report beside the output; empty when none is asked for
  std::string xdts;      // the XDTS exposure sheet beside the output; empty when none
  // `koma batch lipblink --audio-beside` (client/batch/batch_audio_beside.h): the recording
  // sent with this input, as the single-file command's --audio; or why there is none (the
  // item then fails when read, as any unreadable input does).
  std::string audio;
  std::string audio_error;
};

// File name endings the RPC reads, lower case: {".bvh", ".glb", ".gltf", ".vrm", ".vrma"}, or
// {".motion3.json", ".csv"} and for lipblink also the recordings' (AudioExtensions).
// `spine_skeletons` (lipblink with the Spine flags, curves with --animation: every input must
// be a skeleton): {".json"}, so folders collect skeletons and their outputs' sheets are
// NAME.report.html.
std::vector<std::string> ExtensionsOf(const std::string& rpc, bool spine_skeletons = false);

// Recordings `koma batch lipblink` sends as LipBlinkRequest.audio, each written as
// NAME.motion3.json: .wav, .flac, .ogg, .oga, .opus, .mp3 (any case).
const std::vector<std::string>& AudioExtensions();
bool IsAudioPath(const std::string& path);

// A file beside `output`: ("a/b.bvh", ".timing.csv") -> "a/b.timing.csv"; "a/b.motion3.json"
// -> "a/b.timing.csv" (the first of `extensions` that ends the name is replaced; otherwise
// `suffix` is appended).
std::string BesidePath(const std::string& output, const std::vector<std::string>& extensions,
                       const std::string& suffix);
inline std::string TimingPathFor(const std::string& output,
                                 const std::vector<std::string>& extensions) {
  return BesidePath(output, extensions, ".timing.csv");
}
inline std::string ReportPathFor(const std::string& output,
                                 const std::vector<std::string>& extensions) {
  return BesidePath(output, extensions, ".report.html");
}
inline std::string XdtsPathFor(const std::string& output,
                               const std::vector<std::string>& extensions) {
  return BesidePath(output, extensions, ".xdts");
}

// The clips named by `arguments`, in order, each input once:
// - a file: taken whatever its name; its output is out_dir/<file name>;
// - a folder: every file below it whose name ends in one of `extensions` (any case), in
//   path order; each keeps its path below the folder (out_dir itself is never searched);
// - "@LIST": a text file naming one file or folder per line (treated as above; blank lines
//   and lines starting with '#' skipped; relative paths from the current folder).
// `with_timing`, `with_report`, `with_xdts`: fill BatchItem::timing, ::report, ::xdts.
// `audio_beside`: pair each input with the recording beside it (PairRecordingsBeside) before
// the outputs are checked, so a paired recording writes nothing of its own.
// INVALID_ARGUMENT naming the argument (or the list file and line) for a path that does not
// exist, a list that cannot be read, and two inputs whose outputs (or sheets, or reports)
// would be the same file.
absl::StatusOr<std::vector<BatchItem>> DiscoverInputs(const std::vector<std::string>& arguments,
                                                      const std::vector<std::string>& extensions,
                                                      const std::string& out_dir,
                                                      bool with_timing, bool with_report = false,
                                                      bool with_xdts = false,
                                                      bool audio_beside = false);

}  // namespace koma::client::batch

#endif  // KOMA_CLIENT_BATCH_BATCH_INPUTS_H_
