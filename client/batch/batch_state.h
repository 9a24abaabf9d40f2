// What a batch leaves in its output folder so the next run can skip finished clips: the
// options fingerprint each output was made with, in OUTDIR/.koma-batch.json.
#ifndef KOMA_CLIENT_BATCH_BATCH_STATE_H_
#define KOMA_CLIENT_BATCH_BATCH_STATE_H_

#include <map>
#include <string>

#include "absl/status/status.h"
#include "client/batch/batch_inputs.h"

namespace koma::client::batch {

// Output path below the output folder -> fingerprint of the options it was made with.
class Manifest {
 public:
  static constexpr const char* kFileName = ".koma-batch.json";

  // OUTDIR/.koma-batch.json; empty when absent or unreadable (everything is then redone).
  static Manifest Load(const std::string& out_dir);

  // True when item.output (and item.timing, if asked for) exists, is not older than
  // item.input, and was made with `fingerprint`.
  bool UpToDate(const BatchItem& item, const std::string& fingerprint) const;

  void Set(const std::string& relative, const std::string& fingerprint) {
    entries_[relative] = fingerprint;
  }
  void Erase(const std::string& relative) { entries_.erase(relative); }

  // Atomically (temporary file and rename).
  absl::Status Save() const;

 private:
  std::string path_;
  std::map<std::string, std::string> entries_;
};

}  // namespace koma::client::batch

#endif  // KOMA_CLIENT_BATCH_BATCH_STATE_H_
