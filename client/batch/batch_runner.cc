#include "client/batch/batch_runner.h"

#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <set>
#include <thread>
#include <tuple>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "client/channel.h"

namespace koma::client::batch {
namespace {

using Clock = std::chrono::steady_clock;

// Backoff before attempt n+1 after n failed ones: 50 ms doubling, at most 2 s (so 8 attempts
// wait about 4.4 s in all: long enough for a restarted server, short enough to give up).
constexpr double kFirstBackoffS = 0.05;
constexpr double kMaxBackoffS = 2.0;
// A server that answered UNAVAILABLE gets no new calls for 0.5 s, doubling per consecutive
// failure up to 5 s, while another one is up; RESOURCE_EXHAUSTED (full queue) for 0.1 s.
constexpr double kFirstDownS = 0.5;
constexpr double kMaxDownS = 5.0;
constexpr double kExhaustedDownS = 0.1;
// The engine's loop wakes at least this often (signals, progress).
constexpr auto kTick = std::chrono::milliseconds(50);

std::atomic<int> g_interrupts{0};

extern "C" void OnInterrupt(int) { g_interrupts.fetch_add(1); }

// SIGINT and SIGTERM count into g_interrupts while it lives; the previous handlers after.
class InterruptGuard {
 public:
  InterruptGuard() {
    g_interrupts.store(0);
    struct sigaction action = {};
    action.sa_handler = OnInterrupt;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~InterruptGuard() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  struct sigaction old_int_ = {};
  struct sigaction old_term_ = {};
};

Clock::duration Seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

std::string CodeName(grpc::StatusCode code) {
  // absl's canonical code names are gRPC's ("INVALID_ARGUMENT", ...).
  return absl::StatusCodeToString(static_cast<absl::StatusCode>(code));
}

struct Server {
  std::string name;
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<v1::Retime::Stub> stub;
  int in_flight = 0;
  int failures = 0;  // consecutive UNAVAILABLE answers
  Clock::time_point down_until;
};

struct Task {
  size_t index = 0;
  std::unique_ptr<Clip> clip;
  std::shared_ptr<grpc::ClientContext> context;  // of the current attempt
  int attempts = 0;
  int server = -1;  // of the last attempt
  Clock::time_point due;  // a retry's earliest send time
};

class Runner {
 public:
  Runner(const std::vector<BatchItem>& items, std::vector<ItemResult> results, const Rpc& rpc,
         const RunnerSettings& settings, Progress& progress,
         const std::function<void(size_t)>& on_written)
      : items_(items),
        results_(std::move(results)),
        rpc_(rpc),
        settings_(settings),
        progress_(progress),
        on_written_(on_written) {}

  RunResult Run() {
    const Clock::time_point start = Clock::now();
    InterruptGuard interrupts;
    counts_.total = items_.size();
    for (size_t i = 0; i < results_.size(); ++i) {
      if (results_[i].status == ItemStatus::kUpToDate) {
        ++counts_.up_to_date;
      } else {
        to_read_.push_back(i);
      }
    }
    for (const std::string& name : settings_.servers) {
      Server server;
      server.name = name;
      absl::StatusOr<std::shared_ptr<grpc::Channel>> channel = MakeChannel(name);
      if (channel.ok()) {  // the command checked the list; an error here leaves it unused
        server.channel = *channel;
        server.stub = v1::Retime::NewStub(server.channel);
        servers_.push_back(std::move(server));
      }
    }
    jobs_ = settings_.jobs > 0 ? settings_.jobs : 2 * static_cast<int>(servers_.size());
    capacity_ = static_cast<size_t>(jobs_ + std::max(1, settings_.io_threads));

    std::vector<std::thread> pool;
    for (int t = 0; t < std::max(1, settings_.io_threads); ++t) {
      pool.emplace_back([this] { PoolLoop(); });
    }
    MainLoop();
    {
      std::lock_guard<std::mutex> lock(mu_);
      pool_done_ = true;
    }
    pool_cv_.notify_all();
    for (std::thread& thread : pool) thread.join();

    RunResult result;
    result.items = std::move(results_);
    result.counts = counts_;
    result.interrupted = g_interrupts.load() > 0;
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  }

 private:
  void MainLoop() {
    std::unique_lock<std::mutex> lock(mu_);
    while (true) {
      const Clock::time_point now = Clock::now();
      const int interrupts = g_interrupts.load();
      if (interrupts >= 1 && !stopping_) {
        stopping_ = true;  // clips read or waiting for a retry are left not done
        ready_.clear();
        retries_.clear();
        progress_.Line("koma: stopping after the calls in flight (Ctrl-C again to cancel them)");
      }
      if (interrupts >= 2 && !cancelled_) {
        cancelled_ = true;
        std::vector<std::shared_ptr<grpc::ClientContext>> contexts;
        for (const Task* task : in_flight_tasks_) contexts.push_back(task->context);
        lock.unlock();  // TryCancel may run a call's callback, which takes the lock
        for (const auto& context : contexts) context->TryCancel();
        lock.lock();
      }
      while (!completed_.empty()) {
        auto [task, status] = std::move(completed_.front());
        completed_.pop_front();
        HandleCompletion(std::move(task), status, now);
      }
      std::vector<Task*> to_start;
      while (!stopping_ && in_flight_ < jobs_) {
        std::unique_ptr<Task> task = NextToSend(now);
        if (task == nullptr) break;
        const int s = PickServer(*task, now);
        task->server = s;
        ++task->attempts;
        task->context = std::make_shared<grpc::ClientContext>();
        SetDeadline(task->context.get(), settings_.deadline_seconds);
        ++servers_[s].in_flight;
        ++in_flight_;
        in_flight_tasks_.insert(task.get());
        to_start.push_back(task.release());  // owned by the call until its callback
      }
      if (!to_start.empty()) {
        pool_cv_.notify_all();  // room to read more
        lock.unlock();
        for (Task* task : to_start) {
          task->clip->Start(*servers_[task->server].stub, task->context.get(),
                            [this, task](grpc::Status status) {
                              std::lock_guard<std::mutex> guard(mu_);
                              completed_.emplace_back(std::unique_ptr<Task>(task),
                                                      std::move(status));
                              main_cv_.notify_one();
                            });
        }
        lock.lock();
        continue;  // look for completions before waiting
      }
      progress_.Update(counts_);
      const bool reading_left = !stopping_ && next_read_ < to_read_.size();
      if (in_flight_ == 0 && completed_.empty() && ready_.empty() && retries_.empty() &&
          reading_ == 0 && writing_ == 0 && !reading_left) {
        break;
      }
      Clock::time_point wake = now + kTick;
      for (const auto& task : retries_) wake = std::min(wake, task->due);
      main_cv_.wait_until(lock, wake);
    }
  }

  // The earliest retry that is due, else the next clip read; nullptr when neither.
  std::unique_ptr<Task> NextToSend(Clock::time_point now) {
    auto due = retries_.end();
    for (auto it = retries_.begin(); it != retries_.end(); ++it) {
      if ((*it)->due <= now && (due == retries_.end() || (*it)->due < (*due)->due)) due = it;
    }
    if (due != retries_.end()) {
      std::unique_ptr<Task> task = std::move(*due);
      retries_.erase(due);
      return task;
    }
    if (ready_.empty()) return nullptr;
    std::unique_ptr<Task> task = std::move(ready_.front());
    ready_.pop_front();
    return task;
  }

  // A server that is up, other than the one a retry just failed on, with the fewest calls
  // in flight; ties go round the list. When every server is down, the least loaded one
  // (the call fails fast and comes back as a retry with backoff).
  int PickServer(const Task& task, Clock::time_point now) {
    const int n = static_cast<int>(servers_.size());
    int best = -1;
    std::tuple<bool, bool, int> best_key;
    for (int k = 0; k < n; ++k) {
      const int i = (next_server_ + k) % n;
      Server& server = servers_[i];
      const bool down = server.down_until > now ||
                        server.channel->GetState(false) == GRPC_CHANNEL_TRANSIENT_FAILURE;
      const bool just_failed = n > 1 && task.attempts > 0 && i == task.server;
      const std::tuple<bool, bool, int> key{down, just_failed, server.in_flight};
      if (best < 0 || key < best_key) {
        best = i;
        best_key = key;
      }
    }
    next_server_ = (best + 1) % n;
    return best;
  }

  void HandleCompletion(std::unique_ptr<Task> task, const grpc::Status& status,
                        Clock::time_point now) {
    Server& server = servers_[task->server];
    --server.in_flight;
    --in_flight_;
    in_flight_tasks_.erase(task.get());
    ItemResult& result = results_[task->index];
    result.attempts = task->attempts;
    result.server = server.name;
    if (status.ok()) {
      server.failures = 0;
      server.down_until = Clock::time_point();
      ++writing_;
      to_write_.push_back(std::move(task));
      pool_cv_.notify_one();
      return;
    }
    const grpc::StatusCode code = status.error_code();
    if (code == grpc::StatusCode::UNAVAILABLE) {
      ++server.failures;
      server.down_until =
          now + Seconds(std::min(kMaxDownS, kFirstDownS * (1 << std::min(server.failures - 1, 8))));
    } else if (code == grpc::StatusCode::RESOURCE_EXHAUSTED) {
      server.down_until = now + Seconds(kExhaustedDownS);
    }
    const bool retryable =
        code == grpc::StatusCode::UNAVAILABLE || code == grpc::StatusCode::RESOURCE_EXHAUSTED;
    if (stopping_ && (retryable || code == grpc::StatusCode::CANCELLED)) return;  // not done
    if (retryable && task->attempts < settings_.max_attempts) {
      ++counts_.retried;
      task->due = now + Seconds(std::min(
                            kMaxBackoffS, kFirstBackoffS * (1 << std::min(task->attempts - 1, 8))));
      retries_.push_back(std::move(task));
      return;
    }
    std::string error = absl::StrCat(items_[task->index].input, ": ", CodeName(code), ": ",
                                     status.error_message());
    if (task->attempts > 1) absl::StrAppend(&error, " (after ", task->attempts, " attempts)");
    Fail(task->index, CodeName(code), error);
  }

  void Fail(size_t index, const std::string& code, const std::string& error) {
    ItemResult& result = results_[index];
    result.status = ItemStatus::kFailed;
    result.code = code;
    result.error = error;
    ++counts_.failed;
    progress_.Failure(absl::StrCat("koma: ", error));
  }

  // Pool threads: write answers first (they hold memory and finish clips), else read the
  // next clip while fewer than `capacity_` wait to be sent.
  void PoolLoop() {
    std::unique_lock<std::mutex> lock(mu_);
    while (true) {
      if (!to_write_.empty()) {
        std::unique_ptr<Task> task = std::move(to_write_.front());
        to_write_.pop_front();
        lock.unlock();
        const absl::Status status = task->clip->Write(items_[task->index]);
        lock.lock();
        --writing_;
        if (status.ok()) {
          results_[task->index].status = ItemStatus::kOk;
          ++counts_.ok;
          if (on_written_) on_written_(task->index);
          if (settings_.verbose) {
            const ItemResult& r = results_[task->index];
            progress_.Line(absl::StrCat("koma: wrote ", items_[task->index].output, " (server ",
                                        r.server, ", attempts ", r.attempts, ")"));
          }
        } else {
          Fail(task->index, absl::StatusCodeToString(status.code()), std::string(status.message()));
        }
        main_cv_.notify_one();
        continue;
      }
      if (!stopping_ && next_read_ < to_read_.size() && ready_.size() + reading_ < capacity_) {
        const size_t index = to_read_[next_read_++];
        ++reading_;
        lock.unlock();
        absl::StatusOr<std::unique_ptr<Clip>> clip = rpc_.Read(items_[index]);
        lock.lock();
        --reading_;
        if (!clip.ok()) {
          Fail(index, absl::StatusCodeToString(clip.status().code()),
               std::string(clip.status().message()));
        } else if (!stopping_) {
          auto task = std::make_unique<Task>();
          task->index = index;
          task->clip = *std::move(clip);
          ready_.push_back(std::move(task));
        }
        main_cv_.notify_one();
        continue;
      }
      if (pool_done_) return;
      pool_cv_.wait(lock);
    }
  }

  const std::vector<BatchItem>& items_;
  std::vector<ItemResult> results_;
  const Rpc& rpc_;
  const RunnerSettings& settings_;
  Progress& progress_;
  const std::function<void(size_t)>& on_written_;

  std::vector<Server> servers_;
  int jobs_ = 0;
  size_t capacity_ = 0;  // clips read ahead of sending, at most
  int next_server_ = 0;

  std::mutex mu_;  // guards everything below (and progress_, results_, counts_)
  std::condition_variable main_cv_;
  std::condition_variable pool_cv_;
  std::vector<size_t> to_read_;  // indices of the clips to do, in order
  size_t next_read_ = 0;
  int reading_ = 0;
  std::deque<std::unique_ptr<Task>> ready_;     // read, waiting to be sent
  std::vector<std::unique_ptr<Task>> retries_;  // waiting for their backoff
  std::deque<std::pair<std::unique_ptr<Task>, grpc::Status>> completed_;
  std::set<const Task*> in_flight_tasks_;
  int in_flight_ = 0;
  std::deque<std::unique_ptr<Task>> to_write_;
  int writing_ = 0;  // answers queued or being written
  Counts counts_;
  bool stopping_ = false;
  bool cancelled_ = false;
  bool pool_done_ = false;
};

}  // namespace

RunResult RunBatch(const std::vector<BatchItem>& items, std::vector<ItemResult> results,
                   const Rpc& rpc, const RunnerSettings& settings, Progress& progress,
                   const std::function<void(size_t)>& on_written) {
  Runner runner(items, std::move(results), rpc, settings, progress, on_written);
  return runner.Run();
}

}  // namespace koma::client::batch
