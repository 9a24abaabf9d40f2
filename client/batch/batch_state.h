// What a batch leaves in its output folder so the next run can skip finished clips: the
// options fingerprint each output was made with, in OUTDIR/.koma-batch.json.
#ifndef KOMA_CLIENT_BATCH_BATCH_STATE_H_
#define KOMA_CLIENT_BATCH_BATCH_STATE_H_

#include <map>
#include <string>

#include "absl/status/status.h"
#include "client/batch/batch_inputs.h"

namespace koma::client::batch {

// Output path below the output folder -> the input it was made from (absolute) and the
// fingerprint of the options used.
class Manifest {
 public:
  static constexpr const char* kFileName = ".koma-batch.json";

  // OUTDIR/FILE_NAME (a shard's own: .koma-batch.3-of-8.json); empty when absent or
  // unreadable (everything is then redone).
  static Manifest Load(const std::string& out_dir, const std::string& file_name = kFileName);

  // True when item.output (and item.timing and item.report, if asked for) exists, is not older than
  // item.input (nor than item.audio, the recording sent with it), and was made from that input
  // (and that recording) with `fingerprint`.
  bool UpToDate(const BatchItem& item, const std::string& fingerprint) const;

  void Set(const BatchItem& item, const std::string& fingerprint) {
    entries_[item.relative] = Entry{AbsoluteInput(item.input), fingerprint,
                                    item.audio.empty() ? "" : AbsoluteInput(item.audio)};
  }
  void Erase(const std::string& relative) { entries_.erase(relative); }

  // Atomically (temporary file and rename).
  absl::Status Save() const;

 private:
  struct Entry {
    std::string input;
    std::string options;
    std::string audio;  // --audio-beside's recording (absolute); empty: none
  };
  static std::string AbsoluteInput(const std::string& path);

  std::string path_;
  std::map<std::string, Entry> entries_;
};

}  // namespace koma::client::batch

#endif  // KOMA_CLIENT_BATCH_BATCH_STATE_H_
