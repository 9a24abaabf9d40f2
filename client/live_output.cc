#include "client/live_output.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace koma::client {
namespace {

// Milliseconds to 0.001 ms: the clock's noise is far larger.
double RoundMs(double ms) { return std::round(ms * 1000.0) / 1000.0; }

absl::Status WriteLine(std::FILE* out, const std::string& line) {
  if (std::fputs(line.c_str(), out) < 0 || std::fputc('\n', out) == EOF || std::fflush(out) != 0) {
    // The pipe's reader left (`koma live --json | head`): the session ends, as with Ctrl-C.
    if (errno == EPIPE) return absl::CancelledError("the output's reader left");
    return absl::UnavailableError(absl::StrCat(out == stdout ? "standard output" : "standard error",
                                               ": write failed: ", std::strerror(errno)));
  }
  return absl::OkStatus();
}

class JsonSink : public LiveSink {
 public:
  explicit JsonSink(std::FILE* out) : out_(out) {}
  absl::Status Frame(const v1::LiveLipBlinkFrame& frame, const LiveFrameTiming& timing) override {
    return WriteLine(out_, LiveFrameJson(frame, timing));
  }

 private:
  std::FILE* out_;
};

class TextSink : public LiveSink {
 public:
  explicit TextSink(std::FILE* out) : out_(out) {}

  absl::Status Start(const v1::LiveLipBlinkSetup& setup) override {
    fps_ = setup.has_timing_fps() ? setup.timing_fps() : 24.0;
    return absl::OkStatus();
  }

  absl::Status Frame(const v1::LiveLipBlinkFrame& frame, const LiveFrameTiming& timing) override {
    ++frames_;
    ++second_.frames;
    if (frame.speech()) {
      ++speech_frames_;
      ++second_.speech;
      if (!in_speech_) ++speech_runs_;
    }
    in_speech_ = frame.speech();
    if (frame.new_drawing()) {
      ++drawings_;
      ++second_.drawings;
    }
    if (frame.blink_start()) {
      ++blinks_;
      ++second_.blinks;
    }
    late_ms_ = std::max(late_ms_, frame.late_ms());
    second_.wall_max_ms = std::max(second_.wall_max_ms, timing.wall_late_ms);
    second_.wall_sum_ms += timing.wall_late_ms;
    wall_late_ms_.push_back(timing.wall_late_ms);
    // A line when the frame ends a whole second of audio.
    const double end_s = (frame.grid_frame() + 1) / fps_;
    if (std::floor(end_s + 1e-9) > std::floor(frame.grid_frame() / fps_ + 1e-9)) return Flush(end_s);
    return absl::OkStatus();
  }

  absl::Status Close() override {
    if (frames_ == 0) return absl::OkStatus();  // nothing to sum up (the server refused, ...)
    if (second_.frames > 0) {
      if (absl::Status s = Flush(frames_ / fps_); !s.ok()) return s;
    }
    std::vector<double> sorted = wall_late_ms_;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
    const double max = sorted.empty() ? 0.0 : sorted.back();
    return WriteLine(
        out_, absl::StrFormat("koma live: %d frames (%.2f s at %g fps): speech in %d frames (%d "
                              "runs), %d new mouth drawings, %d blinks; decided %.1f ms after a "
                              "frame's end (lookahead), received %.1f ms after its audio was "
                              "sent (median; max %.1f)",
                              frames_, frames_ / fps_, fps_, speech_frames_, speech_runs_,
                              drawings_, blinks_, late_ms_, median, max));
  }

 private:
  absl::Status Flush(double end_s) {
    const absl::Status s = WriteLine(
        out_, absl::StrFormat("%7.1f s  speech %2d/%d frames, %d new drawings, %d blinks; "
                              "received %.0f ms after the audio (max %.0f)",
                              end_s, second_.speech, second_.frames, second_.drawings,
                              second_.blinks, second_.wall_sum_ms / second_.frames,
                              second_.wall_max_ms));
    second_ = Second();
    return s;
  }

  struct Second {
    int frames = 0, speech = 0, drawings = 0, blinks = 0;
    double wall_sum_ms = 0.0, wall_max_ms = 0.0;
  };
  std::FILE* out_;
  double fps_ = 24.0;
  int frames_ = 0, speech_frames_ = 0, speech_runs_ = 0, drawings_ = 0, blinks_ = 0;
  bool in_speech_ = false;
  double late_ms_ = 0.0;
  std::vector<double> wall_late_ms_;
  Second second_;
};

}  // namespace

const char* LiveShapeName(v1::MouthShape shape) {
  switch (shape) {
    case v1::MOUTH_OPEN:
      return "open";
    case v1::MOUTH_MID:
      return "half";
    default:
      return "closed";
  }
}

std::string LiveFrameJson(const v1::LiveLipBlinkFrame& frame, const LiveFrameTiming& timing) {
  nlohmann::ordered_json j{
      {"grid_frame", frame.grid_frame()},
      {"time_s", frame.time_s()},
      {"speech", frame.speech()},
      {"mouth", LiveShapeName(frame.mouth())},
      {"mouth_level", frame.mouth_level()},
      {"new_drawing", frame.new_drawing()},
      {"hold_start", frame.hold_start()},
      {"eyes", LiveShapeName(frame.eyes())},
      {"blink", frame.eyes() != v1::MOUTH_OPEN},
      {"blink_start", frame.blink_start()},
      {"eye_level", frame.eye_level()},
      {"loudness_dbfs", frame.loudness_dbfs()},
      {"noise_floor_dbfs", frame.noise_floor_dbfs()},
      {"late_ms", frame.late_ms()},
      {"wall_late_ms", RoundMs(timing.wall_late_ms)},
      {"wall_s", RoundMs(timing.wall_s * 1000.0) / 1000.0},
  };
  return j.dump();
}

std::unique_ptr<LiveSink> NewLiveJsonSink(std::FILE* out) { return std::make_unique<JsonSink>(out); }

std::unique_ptr<LiveSink> NewLiveTextSink(std::FILE* out) { return std::make_unique<TextSink>(out); }

}  // namespace koma::client
