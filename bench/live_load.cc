// koma_live_load: N concurrent LiveLipBlink streams replayed at real time from recordings, and
// how late each decided grid frame comes back (issue 44; docs/benchmarks.md, "LiveLipBlink:
// latency and streams"; bench/live_scale.sh runs it for growing N).
//
// Each recording is decoded once (formats/audio_reader.h, mixed to mono) and sent as S16LE,
// looped, in chunks of --chunk_ms paced by a steady clock: chunk k of a stream is due when its
// last sample has been "captured", t0 + (k + 1) x chunk, and the streams' t0 are spread evenly
// over one chunk so they do not send in lockstep. Streams take the recordings, chunk sizes and
// lookaheads of the lists round robin. For every grid frame g that arrives:
//   lateness = arrival - the time the chunk holding sample FirstSample(g + 1 + lookahead) - 1
//              (the last sample the decision waits for) was sent, i.e. due: what a capture at
//              real time sees, so a write held back by flow control (a server reading late)
//              counts too. The transport's and the server's delay beyond the lookahead. Budget:
//              one grid frame (1000 / 24 ms) at p99: each frame leaves within the lookahead
//              plus one grid frame of the audio that decides it.
// The tool's own delay is reported beside it: the pacer lag (a chunk handed to its stream after
// it was due: this client starved of CPU) and the write wait (handed to gRPC after it was due:
// the pacer lag plus the wait for the stream's previous write); and the lateness from the write
// (arrival - the deciding chunk handed to gRPC), which leaves both out.
//   total    = arrival - the capture time of the frame's own last sample (t0 + FirstSample(g + 1)
//              / rate): what a viewer sees, chunking and lookahead included.
// Frames decided by the half-close (the last lookahead frames) and frames whose deciding chunk
// was due in the --warmup are not counted. With --server_pid it reads the server's CPU seconds
// (/proc/PID/stat, over the measured window) and resident memory (/proc/PID/status: before any
// connection, and the largest seen while streaming) and divides them by the streams.
// Loopback only; bounded by --duration (+ a 30 s grace for the streams to end) and --streams.
#include <grpcpp/grpcpp.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <queue>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/grid_samples.h"
#include "formats/audio_reader.h"
#include "koma/v1/retime.grpc.pb.h"

namespace {

using Clock = std::chrono::steady_clock;
namespace v1 = koma::v1;

constexpr double kFps = 24.0;
constexpr double kGraceSeconds = 30.0;  // after the last chunk, for the streams to end

struct Options {
  std::string target;
  int streams = 1;
  double duration_s = 20.0;
  double warmup_s = 2.0;
  std::vector<std::string> audio = {"samples/voice.flac"};
  std::vector<int> chunk_ms = {20};
  std::vector<int> lookaheads = {2};
  int channels = 0;  // 0: one per stream (each stream its own connection, as separate clients)
  int pacers = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  int server_pid = 0;
  std::string json_path;
  bool quiet = false;
  bool fail_on_error = false;  // exit 1 when a stream failed or a frame is missing
  bool trace = false;          // every measured frame of stream 0 on stderr
};

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }
Clock::duration Secs(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

// A recording as 16-bit mono little-endian bytes, with its first `pad` samples appended again so
// that any chunk of at most `pad` samples starting inside it is contiguous (the replay loops).
struct Recording {
  std::string path;
  int rate = 0;
  int64_t samples = 0;  // before the padding
  std::string pcm;
};

absl::StatusOr<Recording> LoadRecording(const std::string& path, int max_chunk_ms) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat("--audio: cannot read ", path));
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string bytes = buffer.str();
  auto decoder = koma::formats::AudioDecoder::Open(bytes, koma::formats::AudioLimits{});
  if (!decoder.ok()) return decoder.status();
  Recording r;
  r.path = path;
  r.rate = (*decoder)->info().sample_rate;
  std::vector<int16_t> s16;
  for (;;) {
    auto block = (*decoder)->Next();
    if (!block.ok()) return block.status();
    if (block->empty()) break;
    for (float x : *block) {
      s16.push_back(static_cast<int16_t>(std::clamp(std::lround(x * 32768.0f), -32768L, 32767L)));
    }
  }
  if (s16.empty()) return absl::InvalidArgumentError(absl::StrCat(path, ": no samples"));
  r.samples = static_cast<int64_t>(s16.size());
  const int64_t pad = static_cast<int64_t>(r.rate) * max_chunk_ms / 1000 + 1;
  for (int64_t i = 0; i < pad; ++i) s16.push_back(s16[static_cast<size_t>(i % r.samples)]);
  r.pcm.resize(s16.size() * 2);
  for (size_t i = 0; i < s16.size(); ++i) {  // little-endian whatever the host
    const auto u = static_cast<uint16_t>(s16[i]);
    r.pcm[2 * i] = static_cast<char>(u & 0xff);
    r.pcm[2 * i + 1] = static_cast<char>(u >> 8);
  }
  return r;
}

// One frame's figures, milliseconds.
struct Sample {
  double lateness = 0.0, total = 0.0, from_write = 0.0;
};

// One chunk's delays on this side, milliseconds.
struct SendDelay {
  double pacer = 0.0, write = 0.0;
};

class Stream final : public grpc::ClientBidiReactor<v1::LiveLipBlinkRequest, v1::LiveLipBlinkFrame> {
 public:
  Stream(const Recording& rec, int chunk_ms, int lookahead, Clock::time_point t0,
         double duration_s, Clock::time_point measure_from)
      : rec_(rec),
        grid_(rec.rate, kFps),
        chunk_samples_(static_cast<int64_t>(rec.rate) * chunk_ms / 1000),
        lookahead_(lookahead),
        t0_(t0),
        measure_from_(measure_from) {
    chunks_ = std::max<int64_t>(
        1, static_cast<int64_t>(std::llround(duration_s * rec.rate / chunk_samples_)));
    written_at_.resize(static_cast<size_t>(chunks_));
  }

  int lookahead() const { return lookahead_; }
  void set_trace(bool trace) { trace_ = trace; }
  int64_t chunks() const { return chunks_; }
  Clock::time_point Due(int64_t k) const {
    return t0_ + Secs(static_cast<double>((k + 1) * chunk_samples_) / rec_.rate);
  }

  void Start(v1::Retime::Stub* stub, double deadline_s) {
    context_.set_deadline(std::chrono::system_clock::now() + Secs(deadline_s));
    stub->async()->LiveLipBlink(&context_, this);
    auto* setup = request_.mutable_setup();
    setup->set_sample_rate(rec_.rate);
    setup->set_channels(1);
    setup->set_sample_format(v1::LIVE_SAMPLE_S16LE);
    setup->set_lookahead_frames(lookahead_);
    writing_ = true;
    StartWrite(&request_);
    StartRead(&frame_);
    AddHold();  // the pacer writes from outside the reactions
    StartCall();
  }

  // From the pacer: chunk k is due (k = 0, 1, ... in order).
  void ChunkDue(int64_t k) {
    const Clock::time_point now = Clock::now();
    bool write = false, release = false;
    {
      std::lock_guard<std::mutex> lock(mu_);
      due_ = k + 1;
      if (Due(k) >= measure_from_) pacer_lag_.push_back(Ms(now - Due(k)));
      if (broken_) {
        release = ReleaseLocked();
      } else if (!writing_) {
        write = PrepareLocked();
      }
    }
    if (write) StartWrite(&request_);
    if (release) RemoveHold();
  }

  void OnWriteDone(bool ok) override {
    bool write = false, release = false, writes_done = false;
    {
      std::lock_guard<std::mutex> lock(mu_);
      writing_ = false;
      if (!ok) {
        broken_ = true;
        release = ReleaseLocked();
      } else if (next_ < due_) {
        write = PrepareLocked();
      } else if (next_ == chunks_) {
        writes_done = true;
        release = ReleaseLocked();
      }
    }
    if (write) StartWrite(&request_);
    if (writes_done) StartWritesDone();
    if (release) RemoveHold();
  }

  void OnReadDone(bool ok) override {
    const Clock::time_point now = Clock::now();
    if (!ok) return;
    const int64_t g = frame_.grid_frame();
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (g != expected_frame_) ++out_of_order_;
      expected_frame_ = g + 1;
      ++frames_;
      const int64_t decisive = grid_.FirstSample(g + 1 + lookahead_) - 1;
      const int64_t chunk = decisive / chunk_samples_;
      if (chunk < chunks_ && Due(chunk) >= measure_from_) {
        const Clock::time_point end =
            t0_ + Secs(static_cast<double>(grid_.FirstSample(g + 1)) / rec_.rate);
        samples_.push_back({Ms(now - Due(chunk)), Ms(now - end),
                            Ms(now - written_at_[static_cast<size_t>(chunk)])});
        if (trace_) {
          std::fprintf(stderr, "frame %lld: chunk %lld, lateness %.2f ms, total %.2f ms, "
                       "server late_ms %.2f\n", static_cast<long long>(g),
                       static_cast<long long>(chunk), samples_.back().lateness,
                       samples_.back().total, frame_.late_ms());
        }
      }
    }
    StartRead(&frame_);
  }

  void OnDone(const grpc::Status& status) override {
    std::lock_guard<std::mutex> lock(mu_);
    status_ = status;
    done_ = true;
    done_cv_.notify_all();
  }

  // Waits for OnDone until `deadline`; false if it has not come.
  bool WaitDone(Clock::time_point deadline) {
    std::unique_lock<std::mutex> lock(mu_);
    return done_cv_.wait_until(lock, deadline, [this] { return done_; });
  }
  void Cancel() { context_.TryCancel(); }

  // After WaitDone.
  const grpc::Status& status() const { return status_; }
  const std::vector<Sample>& samples() const { return samples_; }
  const std::vector<double>& pacer_lag() const { return pacer_lag_; }
  const std::vector<double>& write_wait() const { return write_wait_; }
  int64_t frames() const { return frames_; }
  int64_t out_of_order() const { return out_of_order_; }
  // Grid frames the audio sent covers (the last may be partial): what a full answer holds.
  int64_t ExpectedFrames() const {
    const int64_t sent = chunks_ * chunk_samples_;
    int64_t g = static_cast<int64_t>(std::floor(sent * kFps / rec_.rate));
    while (grid_.FirstSample(g) < sent) ++g;
    return g;
  }

 private:
  // Fills request_ with chunk next_ and records when it goes; the caller writes it.
  bool PrepareLocked() {
    const int64_t k = next_++;
    const int64_t offset = (k * chunk_samples_) % rec_.samples;
    request_.set_audio(rec_.pcm.data() + 2 * offset, static_cast<size_t>(2 * chunk_samples_));
    const Clock::time_point now = Clock::now();
    written_at_[static_cast<size_t>(k)] = now;
    if (Due(k) >= measure_from_) write_wait_.push_back(Ms(now - Due(k)));
    writing_ = true;
    return true;
  }
  bool ReleaseLocked() {
    if (released_) return false;
    released_ = true;
    return true;
  }

  const Recording& rec_;
  const koma::GridSamples grid_;
  const int64_t chunk_samples_;
  const int lookahead_;
  const Clock::time_point t0_, measure_from_;
  int64_t chunks_ = 0;
  bool trace_ = false;
  grpc::ClientContext context_;

  std::mutex mu_;
  std::condition_variable done_cv_;
  v1::LiveLipBlinkRequest request_;  // the write in flight
  v1::LiveLipBlinkFrame frame_;      // the read in flight
  int64_t due_ = 0, next_ = 0;       // chunks due; the next chunk to write
  bool writing_ = false, broken_ = false, released_ = false, done_ = false;
  std::vector<Clock::time_point> written_at_;  // per chunk, when handed to gRPC
  std::vector<Sample> samples_;
  std::vector<double> pacer_lag_, write_wait_;
  int64_t frames_ = 0, expected_frame_ = 0, out_of_order_ = 0;
  grpc::Status status_;
};

// The server's CPU seconds (user + system) and resident memory, from /proc.
std::optional<double> ProcCpuSeconds(int pid) {
  std::ifstream in(absl::StrCat("/proc/", pid, "/stat"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t paren = text.rfind(')');
  if (paren == std::string::npos) return std::nullopt;
  std::istringstream fields(text.substr(paren + 2));
  std::string field;
  double utime = 0, stime = 0;
  for (int i = 3; fields >> field; ++i) {  // field 3 is the state; 14 utime, 15 stime
    if (i == 14) utime = std::stod(field);
    if (i == 15) {
      stime = std::stod(field);
      return (utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
    }
  }
  return std::nullopt;
}

std::optional<double> ProcRssMiB(int pid, const char* key = "VmRSS:") {
  std::ifstream in(absl::StrCat("/proc/", pid, "/status"));
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) == 0) return std::stod(line.substr(std::strlen(key))) / 1024.0;
  }
  return std::nullopt;
}

struct Percentiles {
  int64_t n = 0;
  double p50 = 0, p95 = 0, p99 = 0, max = 0;
};

Percentiles Summarise(std::vector<double> v) {
  Percentiles p;
  p.n = static_cast<int64_t>(v.size());
  if (v.empty()) return p;
  std::sort(v.begin(), v.end());
  auto at = [&](double q) {  // nearest rank
    const auto rank = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
  };
  p.p50 = at(0.50), p.p95 = at(0.95), p.p99 = at(0.99), p.max = v.back();
  return p;
}

nlohmann::json ToJson(const Percentiles& p) {
  return {{"n", p.n}, {"p50", p.p50}, {"p95", p.p95}, {"p99", p.p99}, {"max", p.max}};
}
std::string ToText(const Percentiles& p) {
  char line[160];
  std::snprintf(line, sizeof line, "p50 %7.2f  p95 %7.2f  p99 %7.2f  max %7.2f", p.p50, p.p95,
                p.p99, p.max);
  return line;
}

// A pacer: the chunks of streams first, first + step, ... in due order, from one thread (the
// writes it starts run inline on it, so one pacer tops out near a core).
void Pace(std::vector<std::unique_ptr<Stream>>& streams, size_t first, size_t step,
          const std::atomic<bool>& stop) {
  using Item = std::pair<Clock::time_point, std::pair<size_t, int64_t>>;  // due, stream, chunk
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  for (size_t i = first; i < streams.size(); i += step) heap.push({streams[i]->Due(0), {i, 0}});
  while (!heap.empty() && !stop.load()) {
    const Item item = heap.top();
    if (Clock::now() < item.first) std::this_thread::sleep_until(item.first);
    heap.pop();
    const auto [i, k] = item.second;
    streams[i]->ChunkDue(k);
    if (k + 1 < streams[i]->chunks()) heap.push({streams[i]->Due(k + 1), {i, k + 1}});
  }
}

template <typename T>
std::string Join(const std::vector<T>& v) {
  return absl::StrJoin(v, ",");
}

int Run(const Options& o) {
  // The recordings, decoded once.
  const int max_chunk_ms = *std::max_element(o.chunk_ms.begin(), o.chunk_ms.end());
  std::vector<Recording> recordings;
  for (const std::string& path : o.audio) {
    auto r = LoadRecording(path, max_chunk_ms);
    if (!r.ok()) {
      std::fprintf(stderr, "koma_live_load: %s\n", std::string(r.status().message()).c_str());
      return 1;
    }
    recordings.push_back(std::move(*r));
  }
  const int pid = o.server_pid;
  const double rss_idle = pid ? ProcRssMiB(pid).value_or(0.0) : 0.0;

  // Channels, connected before the clock starts.
  const int n_channels = o.channels > 0 ? std::min(o.channels, o.streams) : o.streams;
  std::vector<std::shared_ptr<grpc::Channel>> channels;
  std::vector<std::unique_ptr<v1::Retime::Stub>> stubs;
  for (int i = 0; i < n_channels; ++i) {
    grpc::ChannelArguments args;
    args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // K channels are K connections
    channels.push_back(
        grpc::CreateCustomChannel(o.target, grpc::InsecureChannelCredentials(), args));
    channels.back()->GetState(true);
    stubs.push_back(v1::Retime::NewStub(channels.back()));
  }
  const auto connect_deadline = std::chrono::system_clock::now() + std::chrono::seconds(30);
  for (auto& channel : channels) {
    if (!channel->WaitForConnected(connect_deadline)) {
      std::fprintf(stderr, "koma_live_load: cannot connect to %s within 30 s\n", o.target.c_str());
      return 1;
    }
  }

  // The streams: t0 spread over one chunk, 0.5 s from now.
  const Clock::time_point start = Clock::now() + Secs(0.5);
  const Clock::time_point measure_from = start + Secs(o.warmup_s);
  std::vector<std::unique_ptr<Stream>> streams;
  for (int i = 0; i < o.streams; ++i) {
    const Recording& rec = recordings[static_cast<size_t>(i) % recordings.size()];
    const int chunk_ms = o.chunk_ms[static_cast<size_t>(i) % o.chunk_ms.size()];
    const int lookahead = o.lookaheads[static_cast<size_t>(i) % o.lookaheads.size()];
    const Clock::time_point t0 = start + Secs(chunk_ms / 1000.0 * i / o.streams);
    streams.push_back(
        std::make_unique<Stream>(rec, chunk_ms, lookahead, t0, o.duration_s, measure_from));
  }
  streams[0]->set_trace(o.trace);
  const double cpu_self0 = ProcCpuSeconds(static_cast<int>(getpid())).value_or(0);
  for (size_t i = 0; i < streams.size(); ++i) {
    streams[i]->Start(stubs[i % stubs.size()].get(), o.duration_s + 1.0 + kGraceSeconds);
  }

  // The monitor: the server's CPU over [measure_from, the last chunk due], its largest RSS.
  Clock::time_point last_due = start;
  for (const auto& s : streams) last_due = std::max(last_due, s->Due(s->chunks() - 1));
  std::atomic<bool> stop{false};
  std::optional<double> cpu0, cpu1, self0, self1;
  double rss_peak = 0.0;
  Clock::time_point cpu0_at, cpu1_at;
  std::thread monitor([&] {
    const int self = static_cast<int>(getpid());
    std::this_thread::sleep_until(measure_from);
    cpu0_at = Clock::now();
    if (pid) cpu0 = ProcCpuSeconds(pid);
    self0 = ProcCpuSeconds(self);
    while (!stop.load() && Clock::now() < last_due) {
      if (pid) rss_peak = std::max(rss_peak, ProcRssMiB(pid).value_or(0.0));
      std::this_thread::sleep_until(std::min(last_due, Clock::now() + Secs(0.25)));
    }
    cpu1_at = Clock::now();
    if (pid) cpu1 = ProcCpuSeconds(pid);
    if (pid) rss_peak = std::max(rss_peak, ProcRssMiB(pid).value_or(0.0));
    self1 = ProcCpuSeconds(self);
  });
  std::vector<std::thread> pacers;
  const size_t n_pacers = static_cast<size_t>(std::min(o.pacers, o.streams));
  for (size_t p = 0; p < n_pacers; ++p) {
    pacers.emplace_back([&, p] { Pace(streams, p, n_pacers, stop); });
  }
  for (std::thread& pacer : pacers) pacer.join();

  const Clock::time_point deadline = last_due + Secs(kGraceSeconds);
  int unfinished = 0;
  for (auto& s : streams) {
    if (!s->WaitDone(deadline)) {
      ++unfinished;
      s->Cancel();
    }
  }
  for (auto& s : streams) s->WaitDone(Clock::time_point::max());
  stop = true;
  monitor.join();
  const double cpu_self_all = ProcCpuSeconds(static_cast<int>(getpid())).value_or(0) - cpu_self0;

  // The figures, over all streams and per lookahead.
  std::map<int, std::vector<double>> lateness_by, total_by;
  std::vector<double> lateness, total, from_write, pacer_lag, write_wait;
  std::map<std::string, int> errors;
  int64_t frames = 0, expected = 0, out_of_order = 0;
  for (const auto& s : streams) {
    for (const Sample& x : s->samples()) {
      lateness.push_back(x.lateness), total.push_back(x.total), from_write.push_back(x.from_write);
      lateness_by[s->lookahead()].push_back(x.lateness);
      total_by[s->lookahead()].push_back(x.total);
    }
    pacer_lag.insert(pacer_lag.end(), s->pacer_lag().begin(), s->pacer_lag().end());
    write_wait.insert(write_wait.end(), s->write_wait().begin(), s->write_wait().end());
    frames += s->frames();
    expected += s->ExpectedFrames();
    out_of_order += s->out_of_order();
    if (!s->status().ok()) {
      ++errors[absl::StrCat(s->status().error_code(), " ", s->status().error_message())];
    }
  }
  int failed = 0;
  for (const auto& [_, count] : errors) failed += count;
  const double budget_ms = 1000.0 / kFps;
  const Percentiles late = Summarise(lateness), tot = Summarise(total);
  const Percentiles pacer = Summarise(pacer_lag), wait = Summarise(write_wait);
  const Percentiles written = Summarise(from_write);
  const bool within = failed == 0 && frames == expected && out_of_order == 0 &&
                      late.n > 0 && late.p99 <= budget_ms;
  const double window_s = std::chrono::duration<double>(cpu1_at - cpu0_at).count();

  nlohmann::json j;
  j["target"] = o.target;
  j["streams"] = o.streams;
  j["channels"] = n_channels;
  j["pacers"] = n_pacers;
  j["duration_s"] = o.duration_s;
  j["warmup_s"] = o.warmup_s;
  j["chunk_ms"] = o.chunk_ms;
  j["lookaheads"] = o.lookaheads;
  nlohmann::json recs = nlohmann::json::array();
  for (const Recording& r : recordings) {
    recs.push_back({{"path", r.path}, {"rate", r.rate},
                    {"seconds", static_cast<double>(r.samples) / r.rate}});
  }
  j["recordings"] = recs;
  j["frames"] = frames;
  j["frames_expected"] = expected;
  j["frames_measured"] = late.n;
  j["out_of_order"] = out_of_order;
  j["streams_failed"] = failed;
  j["streams_unfinished"] = unfinished;
  j["errors"] = errors;
  j["budget_ms"] = budget_ms;
  j["within_budget"] = within;
  j["lateness_ms"] = ToJson(late);
  j["total_ms"] = ToJson(tot);
  j["lateness_from_write_ms"] = ToJson(written);
  j["pacer_lag_ms"] = ToJson(pacer);
  j["write_wait_ms"] = ToJson(wait);
  for (const auto& [la, v] : lateness_by) {
    j["by_lookahead"][std::to_string(la)] = {{"lateness_ms", ToJson(Summarise(v))},
                                             {"total_ms", ToJson(Summarise(total_by[la]))}};
  }
  j["window_s"] = window_s;
  if (self0 && self1 && window_s > 0) {
    j["client_cpu_percent"] = 100.0 * (*self1 - *self0) / window_s;
  }
  j["client_cpu_s"] = cpu_self_all;
  if (pid && cpu0 && cpu1 && window_s > 0) {
    const double cpu = *cpu1 - *cpu0;
    j["server"] = {{"pid", pid},
                   {"cpu_s", cpu},
                   {"cpu_percent", 100.0 * cpu / window_s},
                   {"cpu_percent_per_stream", 100.0 * cpu / window_s / o.streams},
                   {"rss_idle_mib", rss_idle},
                   {"rss_peak_mib", rss_peak},
                   {"mib_per_stream", (rss_peak - rss_idle) / o.streams}};
  }

  if (!o.quiet) {
    std::printf("koma_live_load: %d streams over %d connections to %s, %g s each (warmup %g s); "
                "chunks %s ms; lookahead %s; %zu recordings; %zu pacers\n",
                o.streams, n_channels, o.target.c_str(), o.duration_s, o.warmup_s,
                Join(o.chunk_ms).c_str(), Join(o.lookaheads).c_str(), recordings.size(), n_pacers);
    std::printf("frames %lld of %lld expected (%lld measured), out of order %lld, streams failed "
                "%d (unfinished %d)\n",
                static_cast<long long>(frames), static_cast<long long>(expected),
                static_cast<long long>(late.n), static_cast<long long>(out_of_order), failed,
                unfinished);
    for (const auto& [what, count] : errors) std::printf("  error x%d: %s\n", count, what.c_str());
    std::printf("lateness ms (arrival - deciding chunk due): %s  budget %.1f: %s\n",
                ToText(late).c_str(), budget_ms, within ? "within" : "OVER");
    std::printf("total ms (arrival - end of the frame's audio): %s\n", ToText(tot).c_str());
    std::printf("from the write ms (arrival - chunk to gRPC): %s\n", ToText(written).c_str());
    std::printf("pacer lag ms (chunk to its stream - due):     %s\n", ToText(pacer).c_str());
    std::printf("write wait ms (chunk to gRPC - due):          %s\n", ToText(wait).c_str());
    if (lateness_by.size() > 1) {
      for (const auto& [la, v] : lateness_by) {
        std::printf("  lookahead %d: lateness %s | total p99 %.2f\n", la,
                    ToText(Summarise(v)).c_str(), Summarise(total_by[la]).p99);
      }
    }
    if (j.contains("server")) {
      const auto& s = j["server"];
      std::printf("server pid %d: %.2f CPU s in %.1f s = %.1f %% of a core, %.3f %% per stream; "
                  "RSS %.1f -> %.1f MiB, %.3f MiB per stream\n",
                  pid, s["cpu_s"].get<double>(), window_s, s["cpu_percent"].get<double>(),
                  s["cpu_percent_per_stream"].get<double>(), s["rss_idle_mib"].get<double>(),
                  s["rss_peak_mib"].get<double>(), s["mib_per_stream"].get<double>());
    }
    if (j.contains("client_cpu_percent")) {
      std::printf("this client: %.1f %% of a core while measured\n",
                  j["client_cpu_percent"].get<double>());
    }
  }
  if (!o.json_path.empty()) {
    std::ofstream out(o.json_path, std::ios::trunc);
    if (!(out << j.dump(2) << '\n')) {
      std::fprintf(stderr, "koma_live_load: --json: cannot write %s\n", o.json_path.c_str());
      return 1;
    }
  }
  if (o.fail_on_error && (failed > 0 || unfinished > 0 || frames != expected || out_of_order > 0)) {
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "koma_live_load: N LiveLipBlink streams at real time from recordings; prints each grid "
      "frame's lateness past the audio that decides it (p50/p95/p99/max, budget one grid "
      "frame at p99), the total from the end of its audio, and the server's CPU and memory "
      "per stream (--server_pid). Exit 0 after a run (see within_budget; 1 with "
      "--fail_on_error when a stream failed), 1 on a failed setup, 2 on a usage error.\n"
      "  koma_live_load --target 127.0.0.1:PORT --streams 200 --duration 20 --server_pid PID\n"
      "  koma_live_load --target 127.0.0.1:PORT --streams 4 --lookahead 0,1,2,3 --duration 60"};
  app.add_option("--target", o.target, "host:port of koma_server (loopback)")->required();
  app.add_option("--streams,-n", o.streams, "concurrent streams")->check(CLI::Range(1, 20000));
  app.add_option("--duration", o.duration_s, "seconds of audio each stream sends at real time")
      ->check(CLI::Range(0.5, 3600.0))
      ->capture_default_str();
  app.add_option("--warmup", o.warmup_s,
                 "seconds from the start whose deciding chunks are not counted")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--audio", o.audio, "recordings (any libsndfile format), round robin")
      ->delimiter(',')
      ->check(CLI::ExistingFile);
  app.add_option("--chunk_ms,--chunk-ms", o.chunk_ms, "chunk lengths, ms, round robin (10, 20)")
      ->delimiter(',')
      ->check(CLI::Range(1, 1000));
  app.add_option("--lookahead", o.lookaheads, "lookahead_frames, 0..3, round robin")
      ->delimiter(',')
      ->check(CLI::Range(0, 3));
  app.add_option("--channels", o.channels,
                 "connections the streams are spread over; 0: one per stream")
      ->check(CLI::Range(0, 20000));
  app.add_option("--pacers", o.pacers,
                 "threads handing chunks out (streams split among them); default: one a core")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_option("--server_pid,--server-pid", o.server_pid,
                 "the server's PID: its CPU and RSS from /proc, per stream")
      ->check(CLI::PositiveNumber);
  app.add_option("--json", o.json_path, "also write the report as JSON here");
  app.add_flag("--quiet", o.quiet, "no text report");
  app.add_flag("--trace", o.trace, "every measured frame of the first stream on stderr");
  app.add_flag("--fail_on_error,--fail-on-error", o.fail_on_error,
               "exit 1 when a stream failed or a frame is missing or out of order");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (o.target.rfind("127.", 0) != 0 && o.target.rfind("localhost", 0) != 0 &&
      o.target.rfind("[::1]", 0) != 0) {
    std::fprintf(stderr, "koma_live_load: --target must be a loopback address\n");
    return 2;
  }
  return Run(o);
}
