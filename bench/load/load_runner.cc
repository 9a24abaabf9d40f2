#include "bench/load/load_runner.h"

#include <grpcpp/generic/generic_stub.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "client/channel.h"

namespace koma::load {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kMaxMessageBytes = 256 * 1024 * 1024;  // as the server's default

Clock::duration Seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

double Milliseconds(Clock::duration d) {
  return std::chrono::duration<double, std::milli>(d).count();
}

// One call in flight: its context, the reply bytes (never parsed: the client stays light)
// and the time its latency counts from.
struct Call {
  grpc::ClientContext context;
  grpc::ByteBuffer response;
  Clock::time_point scheduled;
};

class Runner {
 public:
  Runner(const LoadOptions& options, const LoadRequest& request,
         const std::vector<std::shared_ptr<grpc::Channel>>& channels)
      : options_(options), method_(request.method) {
    grpc::Slice slice(request.bytes);
    request_ = grpc::ByteBuffer(&slice, 1);
    for (const auto& channel : channels)
      stubs_.push_back(std::make_unique<grpc::GenericStub>(channel));
  }

  RunResult Run();

 private:
  void ClosedLoop();
  void OpenLoop();
  bool MayStillSend(Clock::time_point when);
  bool WaitForSlot(int limit);
  void Send(Clock::time_point scheduled);
  void Done(Call* call, const grpc::Status& status);

  const LoadOptions& options_;
  const std::string method_;
  grpc::ByteBuffer request_;  // shared by every call (slices are reference counted)
  std::vector<std::unique_ptr<grpc::GenericStub>> stubs_;
  Clock::time_point start_, warmup_end_, stop_;
  Clock::time_point last_done_;
  std::mutex mu_;
  std::condition_variable cv_;
  int inflight_ = 0;
  int64_t measured_sent_ = 0;
  int64_t sent_ = 0;
  RunResult result_;
};

RunResult Runner::Run() {
  start_ = Clock::now();
  warmup_end_ = start_ + Seconds(options_.warmup_s);
  const double run_s =
      options_.duration_s ? options_.warmup_s + *options_.duration_s : options_.max_duration_s;
  stop_ = start_ + Seconds(std::min(run_s, options_.max_duration_s));
  last_done_ = warmup_end_;
  if (options_.rate > 0.0) {
    OpenLoop();
  } else {
    ClosedLoop();
  }
  std::unique_lock<std::mutex> lock(mu_);
  cv_.wait(lock, [this] { return inflight_ == 0; });  // bounded by the per-call deadline
  result_.measured_s = std::max(0.0, Milliseconds(last_done_ - warmup_end_) / 1000.0);
  result_.hit_time_cap = options_.count.has_value() && measured_sent_ < *options_.count;
  return std::move(result_);
}

// False once the time is up or --count measured calls were sent.
bool Runner::MayStillSend(Clock::time_point when) {
  if (when >= stop_) return false;
  std::lock_guard<std::mutex> lock(mu_);
  return !options_.count || measured_sent_ < *options_.count;
}

// Waits until fewer than `limit` calls are outstanding; false when the run ended first.
bool Runner::WaitForSlot(int limit) {
  std::unique_lock<std::mutex> lock(mu_);
  return cv_.wait_until(lock, stop_, [&] { return inflight_ < limit; });
}

void Runner::ClosedLoop() {
  while (WaitForSlot(options_.concurrency)) {
    const Clock::time_point now = Clock::now();
    if (!MayStillSend(now)) break;
    Send(now);
  }
}

// Call i is due at start + i / rate; its latency counts from then, so a server that falls
// behind shows its queueing in the percentiles (no coordinated omission).
void Runner::OpenLoop() {
  const double interval_s = 1.0 / options_.rate;
  for (int64_t i = 0;; ++i) {
    const Clock::time_point due = start_ + Seconds(static_cast<double>(i) * interval_s);
    if (!MayStillSend(due)) break;
    std::this_thread::sleep_until(due);
    if (!WaitForSlot(options_.max_inflight)) break;
    Send(due);
  }
}

void Runner::Send(Clock::time_point scheduled) {
  auto* call = new Call;
  call->scheduled = scheduled;
  client::SetDeadline(&call->context, options_.deadline_s);
  size_t channel = 0;
  {
    std::lock_guard<std::mutex> lock(mu_);
    ++inflight_;
    channel = static_cast<size_t>(sent_++) % stubs_.size();
    if (scheduled >= warmup_end_) ++measured_sent_;
  }
  stubs_[channel]->UnaryCall(&call->context, method_, grpc::StubOptions(), &request_,
                             &call->response,
                             [this, call](grpc::Status status) { Done(call, status); });
}

void Runner::Done(Call* call, const grpc::Status& status) {
  const Clock::time_point now = Clock::now();
  const Clock::time_point scheduled = call->scheduled;
  const auto response_bytes = static_cast<int64_t>(call->response.Length());
  const std::string peer = status.ok() ? call->context.peer() : std::string();
  delete call;
  // Everything under the lock, notify included: once inflight_ reaches 0 Run() may return
  // and this Runner go away, so nothing may touch it after the unlock.
  std::lock_guard<std::mutex> lock(mu_);
  if (scheduled < warmup_end_) {
    ++result_.warmup_calls;
  } else {
    last_done_ = std::max(last_done_, now);
    if (status.ok()) {
      if (result_.latencies_ms.empty() || response_bytes < result_.response_bytes_min) {
        result_.response_bytes_min = response_bytes;
      }
      result_.response_bytes_max = std::max(result_.response_bytes_max, response_bytes);
      result_.latencies_ms.push_back(Milliseconds(now - scheduled));
      ++result_.ok_by_peer[peer];
    } else {
      ++result_
            .errors[absl::StatusCodeToString(static_cast<absl::StatusCode>(status.error_code()))];
    }
  }
  --inflight_;
  cv_.notify_all();
}

}  // namespace

std::vector<std::shared_ptr<grpc::Channel>> MakeChannels(const ChannelTarget& target, int count) {
  std::vector<std::shared_ptr<grpc::Channel>> channels;
  for (int i = 0; i < count; ++i) {
    grpc::ChannelArguments args;
    args.SetMaxReceiveMessageSize(kMaxMessageBytes);
    args.SetMaxSendMessageSize(kMaxMessageBytes);
    // A subchannel pool per channel, so K channels are K connections, not one shared.
    args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
    // The koma client's own service config (round_robin over the SERVING servers when
    // balanced; UNAVAILABLE and CANCELLED retried), so the load sees what a real client sees
    // when a server drains or goes away.
    args.SetServiceConfigJSON(client::ClientServiceConfig(target.balanced));
    channels.push_back(
        grpc::CreateCustomChannel(target.uri, grpc::InsecureChannelCredentials(), args));
  }
  return channels;
}

RunResult RunLoad(const LoadOptions& options, const LoadRequest& request,
                  const std::vector<std::shared_ptr<grpc::Channel>>& channels) {
  Runner runner(options, request, channels);
  return runner.Run();
}

}  // namespace koma::load
