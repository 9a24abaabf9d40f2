#include "client/live_command.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <limits>
#include <mutex>
#include <thread>
#include <unistd.h>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "client/channel.h"
#include "client/cli_options.h"
#include "client/command_output.h"
#include "client/files.h"
#include "client/live_sinks.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

using Clock = std::chrono::steady_clock;

// Ctrl-C: the first ends the audio (the stream then ends cleanly); a second exits at once.
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "used in a signal handler");

void OnLiveInterrupt(int) {
  if (g_interrupted.exchange(true)) _exit(130);
}

const char* FormatName(v1::LiveSampleFormat format) {
  return format == v1::LIVE_SAMPLE_F32LE ? "F32LE" : "S16LE";
}

// What the audio thread sent: the sample frames sent so far after each chunk, and when it
// was sent, for LiveFrameTiming.wall_late_ms.
class SentLog {
 public:
  void Add(int64_t end_frames, Clock::time_point at) {
    std::lock_guard<std::mutex> lock(mu_);
    chunks_.push_back({end_frames, at});
  }

  // When the chunk completing sample frame `end_frames` was sent (the last chunk when the
  // audio ended before it). Frames come in order, so earlier chunks are dropped.
  std::optional<Clock::time_point> SentAt(int64_t end_frames) {
    std::lock_guard<std::mutex> lock(mu_);
    while (chunks_.size() > 1 && chunks_.front().end_frames < end_frames) chunks_.pop_front();
    if (chunks_.empty()) return std::nullopt;
    return chunks_.front().at;
  }

 private:
  struct Chunk {
    int64_t end_frames;
    Clock::time_point at;
  };
  std::mutex mu_;
  std::deque<Chunk> chunks_;
};

}  // namespace

absl::Status CheckLiveFlags(const LiveArgs& args) {
  if (!args.input.empty() && !args.device.empty()) {
    return absl::InvalidArgumentError(absl::StrCat("--input ", args.input, " and --device ",
                                                   args.device, ": give one audio source"));
  }
  if (args.input.empty() && args.speed != 1.0) {
    return absl::InvalidArgumentError(
        "--speed: needs --input FILE (a device's audio comes at real time)");
  }
  return CheckOneOnStdout({{"--record", args.record}}, args.json);
}

v1::LiveLipBlinkSetup BuildLiveSetup(const LiveArgs& args, const LiveAudioFormat& format) {
  // lipblink's request builder for the settings both share; the setup takes those it has.
  v1::LipBlinkRequest request = BuildLipBlinkRequest(args.settings, CurveSet{});
  v1::LiveLipBlinkSetup setup;
  setup.set_sample_rate(format.sample_rate);
  setup.set_channels(format.channels);
  setup.set_sample_format(format.sample_format);
  *setup.mutable_mouth() = request.mouth();
  if (request.eyes().ByteSizeLong() > 0) *setup.mutable_eyes() = request.eyes();
  if (request.has_voice_settings()) *setup.mutable_voice_settings() = request.voice_settings();
  if (args.lookahead) setup.set_lookahead_frames(*args.lookahead);
  if (request.has_seed()) setup.set_seed(request.seed());
  if (request.has_timing_fps()) setup.set_timing_fps(request.timing_fps());
  return setup;
}

int RunLive(const LiveArgs& args) {
  if (absl::Status s = CheckLiveFlags(args); !s.ok()) {
    return PrintUsageError("koma live", std::string(s.message()), "koma live --help");
  }
  absl::StatusOr<std::unique_ptr<LiveAudioSource>> opened =
      args.input.empty() ? OpenLiveDevice(args.device.empty() ? "default" : args.device)
                         : OpenLiveFile(args.input);
  if (!opened.ok()) return ReportError(opened.status());
  LiveAudioSource& source = **opened;
  const LiveAudioFormat& format = source.format();
  absl::StatusOr<std::vector<std::unique_ptr<LiveSink>>> made = MakeLiveSinks(args);
  if (!made.ok()) return ReportError(made.status());
  std::vector<std::unique_ptr<LiveSink>>& sinks = *made;
  const v1::LiveLipBlinkSetup setup = BuildLiveSetup(args, format);
  for (auto& sink : sinks) {
    if (absl::Status s = sink->Start(setup); !s.ok()) return ReportError(s);
  }
  absl::StatusOr<std::unique_ptr<v1::Retime::Stub>> stub =
      NewRetimeStub(args.server.empty() ? DefaultServer() : args.server);
  if (!stub.ok()) return ReportError(stub.status());
  if (!args.quiet) {
    std::fprintf(LiveTextStream(args), "koma live: %s, %d Hz, %d channel%s, %s -> %s%s\n",
                 format.description.c_str(), format.sample_rate, format.channels,
                 format.channels == 1 ? "" : "s", FormatName(format.sample_format),
                 (args.server.empty() ? DefaultServer() : args.server).c_str(),
                 args.input.empty() ? " (Ctrl-C ends)" : "");
    std::fflush(LiveTextStream(args));
  }

  grpc::ClientContext context;
  if (args.deadline_seconds > 0) SetDeadline(&context, args.deadline_seconds);
  const Clock::time_point start = Clock::now();
  std::unique_ptr<grpc::ClientReaderWriter<v1::LiveLipBlinkRequest, v1::LiveLipBlinkFrame>>
      stream = (*stub)->LiveLipBlink(&context);

  g_interrupted = false;
  struct sigaction action {};
  struct sigaction previous {};
  action.sa_handler = &OnLiveInterrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &previous);
  // A closed --json pipe is a write error (EPIPE) the JSON sink ends the session on.
  struct sigaction ignore {};
  struct sigaction previous_pipe {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGPIPE, &ignore, &previous_pipe);

  // The audio thread: the setup, the chunks paced to real time, WritesDone.
  SentLog sent_log;
  std::atomic<bool> stop{false};  // a sink failed: end the audio
  absl::Status source_status;
  const int64_t max_frames =
      args.seconds ? static_cast<int64_t>(std::llround(*args.seconds * format.sample_rate))
                   : std::numeric_limits<int64_t>::max();
  std::thread writer([&] {
    v1::LiveLipBlinkRequest request;
    *request.mutable_setup() = setup;
    bool open = stream->Write(request);
    LivePacer pacer(format.sample_rate,
                    source.real_time() ? 0.0 : args.input.empty() ? 1.0 : args.speed);
    const size_t frame_bytes = static_cast<size_t>(format.bytes_per_frame());
    int64_t sent = 0;
    std::string bytes;
    while (open && sent < max_frames && !stop && !g_interrupted) {
      absl::StatusOr<bool> more = source.Next(&bytes);
      if (!more.ok()) {
        source_status = more.status();
        break;
      }
      if (!*more) break;
      int64_t frames = static_cast<int64_t>(bytes.size() / frame_bytes);
      if (frames > max_frames - sent) {
        frames = max_frames - sent;
        bytes.resize(static_cast<size_t>(frames) * frame_bytes);
      }
      pacer.WaitFor(sent + frames, &g_interrupted);
      if (stop || g_interrupted) break;
      sent += frames;
      sent_log.Add(sent, Clock::now());
      request.set_audio(bytes);
      open = stream->Write(request);
    }
    stream->WritesDone();
  });

  // This thread: the frames to the sinks as they come.
  const double fps = setup.has_timing_fps() ? setup.timing_fps() : 24.0;
  std::vector<bool> failed(sinks.size(), false);
  absl::Status sink_status;
  v1::LiveLipBlinkFrame frame;
  int64_t frames_read = 0;
  while (stream->Read(&frame)) {
    ++frames_read;
    const Clock::time_point now = Clock::now();
    const int64_t end_frames = static_cast<int64_t>(
        std::ceil((frame.time_s() + 1.0 / fps) * format.sample_rate - 1e-6));
    LiveFrameTiming timing;
    timing.wall_s = std::chrono::duration<double>(now - start).count();
    if (const std::optional<Clock::time_point> at = sent_log.SentAt(end_frames)) {
      timing.wall_late_ms = std::chrono::duration<double, std::milli>(now - *at).count();
    }
    for (size_t i = 0; i < sinks.size(); ++i) {
      if (failed[i]) continue;
      if (absl::Status s = sinks[i]->Frame(frame, timing); !s.ok()) {
        failed[i] = true;
        // CANCELLED: the sink ends the session cleanly (LiveSink::Frame).
        if (sink_status.ok() && !absl::IsCancelled(s)) sink_status = s;
        stop = true;
      }
    }
  }
  writer.join();
  const grpc::Status status = stream->Finish();
  sigaction(SIGINT, &previous, nullptr);
  sigaction(SIGPIPE, &previous_pipe, nullptr);

  absl::Status close_status;
  for (size_t i = 0; i < sinks.size(); ++i) {
    if (absl::Status s = sinks[i]->Close(); !s.ok() && close_status.ok()) close_status = s;
  }
  if (!status.ok()) {
    if (frames_read > 0 || status.error_code() != grpc::StatusCode::UNAVAILABLE) {
      return ReportRpcError(status);  // e.g. UNAVAILABLE from a server shutting down
    }
    // Never reached: koma's "cannot reach koma_server at ..." with its hint.
    const std::string text =
        RpcErrorText(status, args.server.empty() ? DefaultServer() : args.server);
    for (absl::string_view line : absl::StrSplit(text, '\n', absl::SkipEmpty())) {
      std::fprintf(stderr, "koma: %.*s\n", static_cast<int>(line.size()), line.data());
    }
    return 1;
  }
  if (!source_status.ok()) return ReportError(source_status);
  if (!sink_status.ok()) return ReportError(sink_status);
  if (!close_status.ok()) return ReportError(close_status);
  return 0;
}

}  // namespace koma::client
