#include "server/live_stream.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/live_voice.h"
#include "server/live_lip_blink.h"
#include "server/logging.h"
#include "server/status_mapping.h"

namespace koma::server {

using Clock = std::chrono::steady_clock;

namespace {
// How often the ticker looks at the streams, and how long an ending stream's last frames and
// status may wait for a client that reads nothing before its call is cancelled, seconds.
constexpr double kLiveTickSeconds = 0.25;
constexpr double kUnreadFinishSeconds = 5.0;
// A message may hold at most this many times --live_max_queued_frames grid frames of audio
// (960 by default: 40 s at 24 fps); a live client sends 10-20 ms at a time.
constexpr int64_t kMessageFramesPerQueuedFrame = 4;

double SecondsSince(Clock::time_point t, Clock::time_point now) {
  return std::chrono::duration<double>(now - t).count();
}
}  // namespace

class LiveStream final
    : public grpc::ServerBidiReactor<v1::LiveLipBlinkRequest, v1::LiveLipBlinkFrame> {
 public:
  LiveStream(grpc::CallbackServerContext* context, const RequestLimits& limits,
             LiveStreams* streams)
      : context_(context), limits_(limits), streams_(streams) {
    record_.method = "LiveLipBlink";
    record_.request_id = TakeRequestId(context);
    record_.peer = context_->peer();  // known now; "unknown" once the client is gone
    StartRead(&request_);
  }

  void OnReadDone(bool ok) override {
    Next next;
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (ending_) {
        next = NextLocked();
      } else if (!ok) {  // the client half-closed (or is gone: OnCancel says so)
        if (!voice_) {
          EndLocked(absl::InvalidArgumentError(
                        "setup: the stream ended before its first message, the setup"),
                    false);
        } else {
          voice_->Finish();
          PopLocked();
          EndLocked(absl::OkStatus(), true);
        }
        next = NextLocked();
      } else {
        last_message_ = Clock::now();
        ++messages_;
        const absl::Status s = TakeLocked();
        if (!s.ok()) EndLocked(s, s.code() == absl::StatusCode::kResourceExhausted);
        next = NextLocked(/*read=*/true);
      }
    }
    Run(next);
  }

  void OnWriteDone(bool ok) override {
    Next next;
    {
      std::lock_guard<std::mutex> lock(mu_);
      writing_ = false;
      if (ok) {
        ++frames_out_;
        last_write_ = Clock::now();
      }
      if (!ok) AbortLocked(absl::CancelledError("the client is gone (a write failed)"));
      next = NextLocked();
    }
    Run(next);
  }

  void OnCancel() override {
    Next next;
    {
      std::lock_guard<std::mutex> lock(mu_);
      AbortLocked(absl::CancelledError("the client cancelled the stream or went away"));
      next = NextLocked();
    }
    Run(next);
  }

  void OnDone() override {
    {
      // The call's context goes when this returns: the ticker must not be cancelling it.
      std::unique_lock<std::mutex> lock(mu_);
      done_reacting_ = true;
      cancel_done_.wait(lock, [this] {
        return !cancelling_ || cancel_thread_ == std::this_thread::get_id();
      });
    }
    record_.latency_ms = 1000.0 * SecondsSince(start_, Clock::now());
    record_.frames = frames_out_;
    if (RpcLineLogged(record_)) LogRpc(record_);
    if (streams_->Remove(this)) delete this;
  }

  // From the ticker: a stream without a message for --live_idle_seconds ends; an ending
  // stream whose client reads nothing (its last frames or its status are stuck behind gRPC's
  // flow control) is cancelled once no frame was written for kUnreadFinishSeconds since it
  // began to end (a client that reads slowly is not cut while its last frames drain).
  void Tick(Clock::time_point now) {
    Next next;
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (!ending_ && limits_.live_idle_seconds > 0 &&
          SecondsSince(last_message_, now) > limits_.live_idle_seconds) {
        EndLocked(absl::DeadlineExceededError(absl::StrCat(
                      "no message for ", limits_.live_idle_seconds,
                      " s (the server limit --live_idle_seconds); send audio, even silence, "
                      "or half-close the stream")),
                  false);
      } else if (ending_ && !cancelled_ && !done_reacting_ &&
                 SecondsSince(std::max(end_time_, last_write_), now) > kUnreadFinishSeconds) {
        cancelled_ = true;
        cancelling_ = true;
        cancel_thread_ = std::this_thread::get_id();
        next.cancel = true;
        record_.code = grpc::StatusCode::CANCELLED;
        record_.error = absl::StrCat("the client read nothing for ", kUnreadFinishSeconds,
                                     " s after the stream ended (",
                                     end_status_.error_message().empty()
                                         ? std::string("OK")
                                         : end_status_.error_message(),
                                     "): the call was cancelled");
      }
      if (!next.cancel) next = NextLocked();
    }
    Run(next);
  }

  // Ends the stream with `status` after the frames decided so far (server shutdown).
  void End(const absl::Status& status) {
    Next next;
    {
      std::lock_guard<std::mutex> lock(mu_);
      EndLocked(status, true);
      next = NextLocked();
    }
    Run(next);
  }

 private:
  // What to start once the lock is released: gRPC's operations are never started under it
  // (they may run reactions inline). Reactions, the ticker and EndAll run concurrently, so
  // Finish waits for every read or write another thread decided to start and has not yet
  // (`starting_`): gRPC forbids a write after Finish.
  struct Next {
    bool read = false;
    bool write = false;
    std::optional<grpc::Status> finish;
    bool cancel = false;
  };

  void Run(const Next& next) {
    if (next.write) StartWrite(&out_);
    if (next.read) StartRead(&request_);
    std::optional<grpc::Status> finish = next.finish;
    if (next.write || next.read) {
      std::lock_guard<std::mutex> lock(mu_);
      if (--starting_ == 0 && finish_pending_) {
        finish_pending_ = false;
        finish = end_status_;
      }
    }
    if (finish) Finish(*finish);
    if (next.cancel) {
      context_->TryCancel();  // OnDone waits for this (or runs inside it, on this thread)
      std::lock_guard<std::mutex> lock(mu_);
      cancelling_ = false;
      cancel_done_.notify_all();
    }
  }

  // The message just read: the setup, or audio for the analysis.
  absl::Status TakeLocked() {
    if (!voice_) {
      if (request_.message_case() != v1::LiveLipBlinkRequest::kSetup) {
        return absl::InvalidArgumentError(
            "setup: the first message must be the setup (sample rate, channels, format)");
      }
      absl::StatusOr<LiveVoiceOptions> options = LiveOptionsFromSetup(request_.setup(), limits_);
      if (!options.ok()) return options.status();
      sample_rate_ = options->sample_rate;
      fps_ = options->frame_fps;
      decoder_.emplace(request_.setup().sample_format(), request_.setup().channels());
      voice_.emplace(*options);
      max_samples_ = static_cast<int64_t>(limits_.live_max_seconds * sample_rate_);
      request_.Clear();
      return absl::OkStatus();
    }
    if (request_.message_case() == v1::LiveLipBlinkRequest::kSetup) {
      return absl::InvalidArgumentError(absl::StrCat(
          "setup: message ", messages_ - 1, " is a second setup; a stream has one, first"));
    }
    if (request_.message_case() != v1::LiveLipBlinkRequest::kAudio) {
      return absl::InvalidArgumentError(absl::StrCat(
          "message ", messages_ - 1, " has neither setup nor audio"));
    }
    const std::string& audio = request_.audio();
    record_.bytes_in += static_cast<int64_t>(audio.size());
    if (static_cast<int64_t>(audio.size()) > limits_.live_max_message_bytes) {
      return absl::InvalidArgumentError(absl::StrCat(
          "audio (message ", messages_ - 1, "): ", audio.size(),
          " bytes exceeds the server limit --live_max_message_bytes=",
          limits_.live_max_message_bytes, "; send smaller pieces"));
    }
    // The frames one message may decide: a bound on the memory it holds at once whatever the
    // rate and grid (1 kHz audio on a 1,000 fps grid decides a frame per sample).
    const int64_t frames_in_message = static_cast<int64_t>(
        static_cast<double>(audio.size() / decoder_->bytes_per_frame()) / sample_rate_ * fps_);
    const int64_t max_frames = kMessageFramesPerQueuedFrame * limits_.live_max_queued_frames;
    if (frames_in_message > max_frames) {
      return absl::InvalidArgumentError(absl::StrCat(
          "audio (message ", messages_ - 1, "): ", audio.size(), " bytes hold ",
          frames_in_message, " grid frames of audio, over ", max_frames, " (",
          kMessageFramesPerQueuedFrame, " x --live_max_queued_frames); send smaller pieces, "
          "as they are captured"));
    }
    mono_.clear();
    if (absl::Status s = decoder_->Decode(audio, messages_ - 1, &mono_); !s.ok()) return s;
    request_.Clear();
    // The frames still waiting from earlier messages: those the client could have read.
    const size_t unread = queue_.size();
    absl::Span<const float> samples(mono_);
    const int64_t room = max_samples_ - voice_->samples();
    const bool over = static_cast<int64_t>(samples.size()) > room;
    if (over) samples = samples.first(static_cast<size_t>(std::max<int64_t>(room, 0)));
    voice_->Add(samples);
    if (over) {
      voice_->Finish();
      PopLocked();
      return absl::ResourceExhaustedError(absl::StrCat(
          "audio: the stream reached ", limits_.live_max_seconds,
          " s of audio, the server limit --live_max_seconds; start a new stream"));
    }
    PopLocked();
    if (static_cast<int64_t>(unread) > limits_.live_max_queued_frames) {
      // Not drained: the frames are dropped and the status follows the write in flight.
      const absl::Status s = absl::ResourceExhaustedError(absl::StrCat(
          "the client read none of the last ", limits_.live_max_queued_frames,
          " frames (the server limit --live_max_queued_frames); read the stream's messages as "
          "they come"));
      EndLocked(s, false);
      return s;
    }
    return absl::OkStatus();
  }

  void PopLocked() {
    LiveFrame frame;
    while (voice_->Pop(&frame)) queue_.push_back(frame);
  }

  // The stream ends with `status`: after the waiting frames when `drain`, else now. The first
  // end wins.
  void EndLocked(const absl::Status& status, bool drain) {
    if (ending_) return;
    ending_ = true;
    end_time_ = Clock::now();
    drain_ = drain;
    if (!drain) queue_.clear();
    end_status_ = ToGrpcStatus(status);
    record_.code = end_status_.error_code();
    record_.error = end_status_.error_message();
  }

  // The client is gone: end now (or, if already ending, stop draining); nothing more is written.
  // A client that vanishes mid-stream fails its read first, which looks like a half-close (an
  // OK end): the log line says CANCELLED then.
  void AbortLocked(const absl::Status& status) {
    EndLocked(status, false);
    drain_ = false;
    queue_.clear();
    if (record_.code == grpc::StatusCode::OK) {
      record_.code = grpc::StatusCode::CANCELLED;
      record_.error = std::string(status.message());
    }
  }

  // What to start next; `read`: another read, unless the stream is ending.
  Next NextLocked(bool read = false) {
    Next next;
    next.read = read && !ending_;
    if (!finished_) {
      if (!writing_ && !queue_.empty()) {
        LiveFrameToProto(queue_.front(), sample_rate_, &out_);
        queue_.pop_front();
        writing_ = true;
        next.write = true;
      }
      // An error ends the stream at once, even with a write in flight (gRPC sends the status
      // after it); a drained stream after its last frame is written.
      if (ending_ && (!drain_ || (queue_.empty() && !writing_))) {
        finished_ = true;
        finish_pending_ = true;
        // Its slot frees now, not at OnDone: a client that has its status may open the next
        // stream at once.
        streams_->Release(this);
      }
    }
    if (next.read || next.write) ++starting_;
    if (finish_pending_ && starting_ == 0) {
      finish_pending_ = false;
      next.finish = end_status_;
    }
    return next;
  }

  grpc::CallbackServerContext* const context_;
  const RequestLimits& limits_;
  LiveStreams* const streams_;
  const Clock::time_point start_ = Clock::now();

  std::mutex mu_;
  v1::LiveLipBlinkRequest request_;  // the read in flight writes here
  v1::LiveLipBlinkFrame out_;        // the write in flight reads here
  std::optional<LiveAudioDecoder> decoder_;
  std::optional<LiveVoice> voice_;
  std::vector<float> mono_;
  std::deque<LiveFrame> queue_;
  int sample_rate_ = 0;
  double fps_ = 0.0;  // the grid's frames per second
  int64_t max_samples_ = 0;
  int64_t messages_ = 0;
  int64_t frames_out_ = 0;
  Clock::time_point last_message_ = Clock::now();
  bool writing_ = false;
  bool ending_ = false, drain_ = false;
  Clock::time_point end_time_;
  Clock::time_point last_write_;  // the last frame written
  bool finished_ = false;        // Finish is decided (issued, or pending on `starting_`)
  bool finish_pending_ = false;  // decided, waiting for the reads and writes being started
  int starting_ = 0;             // threads between deciding a read or write and starting it
  bool cancelled_ = false;       // the ticker cancelled the call
  bool cancelling_ = false;      // ... and is inside TryCancel, on cancel_thread_
  std::thread::id cancel_thread_;
  bool done_reacting_ = false;   // OnDone began: the context is about to go
  std::condition_variable cancel_done_;
  grpc::Status end_status_;
  RpcRecord record_;
  int pins_ = 0;      // LiveStreams' mu_: the ticker holds the stream (it must not be deleted)
  bool counted_ = false;  // LiveStreams' mu_: it holds one of --live_max_streams' slots
  bool done_ = false; // LiveStreams' mu_: OnDone ran; the last unpin deletes it

  friend class LiveStreams;
};

LiveStreams::~LiveStreams() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (ticker_.joinable()) ticker_.join();
}

grpc::ServerBidiReactor<v1::LiveLipBlinkRequest, v1::LiveLipBlinkFrame>* LiveStreams::Open(
    grpc::CallbackServerContext* context) {
  auto* stream = new LiveStream(context, limits_, this);
  std::optional<absl::Status> refused;
  {
    // One lock for the check and the count: concurrent opens cannot pass the limit together,
    // and EndAll (which sets ending_ under it) sees every stream counted.
    std::lock_guard<std::mutex> lock(mu_);
    if (ending_) {
      refused = absl::UnavailableError("the server is shutting down; connect to another");
    } else if (open_ >= limits_.live_max_streams) {
      refused = absl::ResourceExhaustedError(
          absl::StrCat(open_, " live streams are in flight, the server limit "
                              "--live_max_streams; retry later or use another server"));
    } else {
      streams_.insert(stream);
      stream->counted_ = true;
      ++open_;
      if (!ticker_.joinable() && !stopping_) ticker_ = std::thread([this] { Tick(); });
    }
  }
  // A refused stream is not counted (a storm of retries must not hold the slots) and is never
  // pinned: its OnDone deletes it. gRPC starts its Finish once it has the reactor.
  if (refused) stream->End(*refused);
  return stream;
}

void LiveStreams::EndAll() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    ending_ = true;
  }
  ForEach([](LiveStream* stream) {
    stream->End(absl::UnavailableError("the server is shutting down; connect to another"));
  });
}

int LiveStreams::in_flight() const {
  std::lock_guard<std::mutex> lock(mu_);
  return static_cast<int>(streams_.size());
}

void LiveStreams::Release(LiveStream* stream) {
  std::lock_guard<std::mutex> lock(mu_);
  if (stream->counted_) --open_;
  stream->counted_ = false;
}

bool LiveStreams::Remove(LiveStream* stream) {
  std::lock_guard<std::mutex> lock(mu_);
  if (stream->counted_) --open_;
  stream->counted_ = false;
  streams_.erase(stream);
  stream->done_ = true;
  return stream->pins_ == 0;
}

template <typename F>
void LiveStreams::ForEach(F f) {
  std::vector<LiveStream*> pinned;
  {
    std::lock_guard<std::mutex> lock(mu_);
    pinned.assign(streams_.begin(), streams_.end());
    for (LiveStream* stream : pinned) ++stream->pins_;
  }
  // gRPC's operations may run a stream's reactions (OnDone too) on this thread: no lock held.
  for (LiveStream* stream : pinned) f(stream);
  std::lock_guard<std::mutex> lock(mu_);
  for (LiveStream* stream : pinned) {
    if (--stream->pins_ == 0 && stream->done_) delete stream;
  }
}

void LiveStreams::Tick() {
  std::unique_lock<std::mutex> lock(mu_);
  while (!stopping_) {
    wake_.wait_for(lock, std::chrono::duration<double>(kLiveTickSeconds));
    if (stopping_ || streams_.empty()) continue;
    lock.unlock();
    const Clock::time_point now = Clock::now();
    ForEach([now](LiveStream* stream) { stream->Tick(now); });
    lock.lock();
  }
}

}  // namespace koma::server
