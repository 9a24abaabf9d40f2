#include "bench/live_echo.h"

#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

#include "core/grid_samples.h"

namespace koma::echo {
namespace {

constexpr double kFps = 24.0;
constexpr int kDefaultLookahead = 2;  // LiveLipBlinkSetup's unset lookahead_frames
// Frames queued for a client that reads nothing before the stream ends (koma_server's
// --live_max_queued_frames default): the echo's memory stays bounded too.
constexpr size_t kMaxQueuedFrames = 240;

class LiveEchoStream final
    : public grpc::ServerBidiReactor<v1::LiveLipBlinkRequest, v1::LiveLipBlinkFrame> {
 public:
  LiveEchoStream() { StartRead(&request_); }

  void OnReadDone(bool ok) override {
    Next next;
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (!ok) {  // half-closed (or gone): the frames the audio reaches into, then OK
        if (grid_) Decide(/*at_end=*/true);
        End(grpc::Status::OK, /*drain=*/true);
      } else if (grpc::Status s = Take(); !s.ok()) {
        End(s, /*drain=*/false);
      }
      next = NextLocked(/*read=*/ok);
    }
    Run(next);
  }

  void OnWriteDone(bool ok) override {
    Next next;
    {
      std::lock_guard<std::mutex> lock(mu_);
      writing_ = false;
      if (!ok) {  // the client is gone: nothing more is written
        End(grpc::Status(grpc::StatusCode::CANCELLED, "a write failed"), false);
        queue_.clear();
      }
      next = NextLocked();
    }
    Run(next);
  }

  void OnDone() override { delete this; }

 private:
  struct Next {
    bool read = false, write = false;
    std::optional<grpc::Status> finish;
  };

  void Run(const Next& next) {
    if (next.write) StartWrite(&out_);
    if (next.read) StartRead(&request_);
    if (next.finish) Finish(*next.finish);
  }

  // The setup (its rate, channels, format and lookahead), or audio: its samples counted.
  grpc::Status Take() {
    if (!grid_) {
      const v1::LiveLipBlinkSetup& setup = request_.setup();
      const int bytes = setup.sample_format() == v1::LIVE_SAMPLE_S16LE   ? 2
                        : setup.sample_format() == v1::LIVE_SAMPLE_F32LE ? 4
                                                                         : 0;
      if (!request_.has_setup() || setup.sample_rate() < 1000 ||
          setup.sample_rate() > 384000 || setup.channels() < 1 || setup.channels() > 64 ||
          bytes == 0) {
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "setup: the first message must be a setup with a sample rate in "
                            "[1000, 384000], 1 to 64 channels and a sample format");
      }
      rate_ = setup.sample_rate();
      bytes_per_frame_ = bytes * setup.channels();
      lookahead_ = setup.has_lookahead_frames() ? setup.lookahead_frames() : kDefaultLookahead;
      grid_.emplace(rate_, kFps);
      return grpc::Status::OK;
    }
    if (request_.audio().size() % static_cast<size_t>(bytes_per_frame_) != 0) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "audio: not a whole number of sample frames");
    }
    samples_ += static_cast<int64_t>(request_.audio().size()) / bytes_per_frame_;
    request_.Clear();
    Decide(/*at_end=*/false);
    if (queue_.size() > kMaxQueuedFrames) {
      return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, "the client reads nothing");
    }
    return grpc::Status::OK;
  }

  // Queues every frame whose deciding audio is in: frame g once sample FirstSample(g + 1 +
  // lookahead) - 1 has arrived (koma's rule); at the end, every frame the audio reaches into.
  void Decide(bool at_end) {
    for (;;) {
      const int64_t g = decided_;
      const int64_t needed = grid_->FirstSample(g + 1 + (at_end ? 0 : lookahead_));
      if (at_end ? grid_->FirstSample(g) >= samples_ : needed > samples_) return;
      v1::LiveLipBlinkFrame frame;
      // Fields as koma's (server/live_lip_blink.cc's LiveFrameToProto), values fixed: the
      // same message size on the wire.
      frame.set_grid_frame(g);
      frame.set_time_s(static_cast<double>(g) / kFps);
      frame.set_mouth(v1::MOUTH_CLOSED);
      frame.set_eyes(v1::MOUTH_OPEN);
      frame.set_eye_level(1.0);
      frame.set_late_ms(1000.0 * static_cast<double>(lookahead_) / kFps);
      frame.set_loudness_dbfs(-30.25);
      frame.set_noise_floor_dbfs(-60.5);
      queue_.push_back(std::move(frame));
      ++decided_;
    }
  }

  void End(const grpc::Status& status, bool drain) {
    if (ending_) return;
    ending_ = true;
    end_status_ = status;
    if (!drain) queue_.clear();
  }

  Next NextLocked(bool read = false) {
    Next next;
    if (finished_) return next;
    next.read = read && !ending_;
    if (!writing_ && !queue_.empty()) {
      out_ = std::move(queue_.front());
      queue_.pop_front();
      writing_ = true;
      next.write = true;
    }
    if (ending_ && queue_.empty() && !writing_) {
      finished_ = true;
      next.finish = end_status_;
    }
    return next;
  }

  std::mutex mu_;
  v1::LiveLipBlinkRequest request_;  // the read in flight writes here
  v1::LiveLipBlinkFrame out_;        // the write in flight reads here
  std::deque<v1::LiveLipBlinkFrame> queue_;
  std::optional<GridSamples> grid_;  // set by the setup
  int rate_ = 0, bytes_per_frame_ = 0, lookahead_ = kDefaultLookahead;
  int64_t samples_ = 0, decided_ = 0;
  bool writing_ = false, ending_ = false, finished_ = false;
  grpc::Status end_status_;
};

}  // namespace

grpc::ServerBidiReactor<v1::LiveLipBlinkRequest, v1::LiveLipBlinkFrame>* OpenLiveEchoStream() {
  return new LiveEchoStream();
}

}  // namespace koma::echo
