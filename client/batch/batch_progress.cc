#include "client/batch/batch_progress.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace koma::client::batch {
namespace {

constexpr double kBarRedrawS = 0.1;  // a terminal bar at most 10 times a second
constexpr int kBarWidth = 30;        // characters between the brackets

std::string Duration(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  if (s < 60) return absl::StrCat(s, " s");
  if (s < 3600) return absl::StrFormat("%ld:%02ld", s / 60, s % 60);
  return absl::StrFormat("%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
}

}  // namespace

Progress::Progress(FILE* out, bool terminal, bool quiet, double plain_every_s)
    : out_(out),
      terminal_(terminal),
      quiet_(quiet),
      plain_every_s_(plain_every_s),
      start_(Clock::now()),
      last_draw_(start_) {}

std::string Progress::Describe(const Counts& counts) const {
  const size_t finished = counts.up_to_date + counts.ok + counts.failed;
  const size_t processed = counts.ok + counts.failed;  // this run's work, skips excluded
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  const double rate = elapsed > 0 ? processed / elapsed : 0;
  std::string text = absl::StrFormat(
      "%zu/%zu (%zu%%), %.1f clips/s", finished, counts.total,
      counts.total == 0 ? 100 : finished * 100 / counts.total, rate);
  if (rate > 0 && finished < counts.total) {
    absl::StrAppend(&text, ", ETA ", Duration((counts.total - finished) / rate));
  }
  absl::StrAppend(&text, ", ", counts.failed, " failed");
  if (counts.up_to_date > 0) absl::StrAppend(&text, ", ", counts.up_to_date, " up to date");
  if (counts.retried > 0) absl::StrAppend(&text, ", ", counts.retried, " retried");
  return text;
}

void Progress::Update(const Counts& counts) {
  if (quiet_) return;
  const Clock::time_point now = Clock::now();
  const double since = std::chrono::duration<double>(now - last_draw_).count();
  if (terminal_) {
    if (since < kBarRedrawS && bar_shown_) return;
    const size_t finished = counts.up_to_date + counts.ok + counts.failed;
    const int filled =
        counts.total == 0 ? kBarWidth : static_cast<int>(finished * kBarWidth / counts.total);
    std::string bar(filled, '=');
    bar.resize(kBarWidth, ' ');
    std::fprintf(out_, "\r\033[K[%s] %s", bar.c_str(), Describe(counts).c_str());
    std::fflush(out_);
    bar_shown_ = true;
  } else {
    if (since < plain_every_s_) return;
    std::fprintf(out_, "koma batch: %s\n", Describe(counts).c_str());
    std::fflush(out_);
  }
  last_draw_ = now;
}

void Progress::ClearBar() {
  if (!bar_shown_) return;
  std::fprintf(out_, "\r\033[K");
  bar_shown_ = false;
}

void Progress::Failure(const std::string& message) { Line(message); }

void Progress::Line(const std::string& message) {
  ClearBar();
  std::fprintf(out_, "%s\n", message.c_str());
  std::fflush(out_);
}

void Progress::Finish() {
  ClearBar();
  std::fflush(out_);
}

}  // namespace koma::client::batch
