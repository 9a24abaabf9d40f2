// Progress of a batch on stderr: a live bar on a terminal, a plain line every few seconds
// otherwise (CI logs), nothing when quiet. Failures are printed as they happen.
#ifndef KOMA_CLIENT_BATCH_BATCH_PROGRESS_H_
#define KOMA_CLIENT_BATCH_BATCH_PROGRESS_H_

#include <chrono>
#include <cstdio>
#include <string>

namespace koma::client::batch {

struct Counts {
  size_t total = 0;       // clips in the batch
  size_t up_to_date = 0;  // skipped: outputs already made with these options
  size_t ok = 0;          // written in this run
  size_t failed = 0;
  size_t retried = 0;  // calls sent again after UNAVAILABLE or RESOURCE_EXHAUSTED
};

class Progress {
 public:
  using Clock = std::chrono::steady_clock;

  // `terminal`: redraw one line in place (stderr is a TTY). `plain_every_s`: seconds between
  // plain lines. `quiet`: no progress at all (failures are still printed).
  Progress(FILE* out, bool terminal, bool quiet, double plain_every_s);

  // Called often (every loop of the batch); draws when due.
  void Update(const Counts& counts);
  // One failure, on its own line (the bar is redrawn below it).
  void Failure(const std::string& message);
  // Any other line (--verbose), kept clear of the bar.
  void Line(const std::string& message);
  // Clears the bar; the summary follows.
  void Finish();

  // "523/1000 (52%), 310.2 clips/s, ETA 2 s, 3 failed".
  std::string Describe(const Counts& counts) const;

 private:
  void ClearBar();

  FILE* out_;
  bool terminal_;
  bool quiet_;
  double plain_every_s_;
  Clock::time_point start_;
  Clock::time_point last_draw_;
  bool bar_shown_ = false;
};

}  // namespace koma::client::batch

#endif  // KOMA_CLIENT_BATCH_BATCH_PROGRESS_H_
