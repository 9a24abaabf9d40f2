#include "server/memory_budget.h"

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"

namespace koma::server {
namespace {

constexpr int64_t kMiB = 1024 * 1024;

std::string MiB(int64_t bytes) { return absl::StrCat((bytes + kMiB - 1) / kMiB, " MiB"); }

// The first line of `path`, trimmed; empty when it cannot be read.
std::string FirstLine(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return std::string(absl::StripAsciiWhitespace(line));
}

// A cgroup limit in bytes, or 0 for none ("max", unreadable, or v1's "no limit", which is
// a number near 2^63 rounded to pages).
int64_t CgroupLimit(const std::string& path) {
  int64_t bytes = 0;
  if (!absl::SimpleAtoi(FirstLine(path), &bytes) || bytes <= 0) return 0;
  if (bytes >= (int64_t{1} << 60)) return 0;
  return bytes;
}

int64_t MemTotal(const std::string& root) {
  std::ifstream in(root + "/proc/meminfo");
  std::string key;
  int64_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit) {
    if (key == "MemTotal:") return kib * 1024;
  }
  return 0;
}

}  // namespace

MemoryBudget::Reservation& MemoryBudget::Reservation::operator=(Reservation&& other) noexcept {
  if (this != &other) {
    Release();
    budget_ = std::exchange(other.budget_, nullptr);
    bytes_ = std::exchange(other.bytes_, 0);
  }
  return *this;
}

absl::Status MemoryBudget::Reservation::Resize(int64_t bytes, const char* what) {
  if (budget_ == nullptr) {
    bytes_ = bytes;
    return absl::OkStatus();
  }
  if (bytes > bytes_) {
    if (!budget_->TryTake(bytes - bytes_)) return budget_->Refusal(bytes, what);
  } else {
    budget_->Give(bytes_ - bytes);
  }
  bytes_ = bytes;
  return absl::OkStatus();
}

void MemoryBudget::Reservation::Release() {
  if (budget_ != nullptr) budget_->Give(bytes_);
  budget_ = nullptr;
  bytes_ = 0;
}

absl::StatusOr<MemoryBudget::Reservation> MemoryBudget::Reserve(int64_t bytes, const char* what) {
  if (!TryTake(bytes)) return Refusal(bytes, what);
  Reservation reservation;
  reservation.budget_ = this;
  reservation.bytes_ = bytes;
  return reservation;
}

void MemoryBudget::ExportMetrics(prometheus::Registry& registry) {
  prometheus::BuildGauge()
      .Name("koma_memory_budget_bytes")
      .Help("The server's memory budget for calls in flight (--max_memory_mb), bytes.")
      .Register(registry)
      .Add({})
      .Set(static_cast<double>(capacity_));
  in_use_gauge_ = &prometheus::BuildGauge()
                       .Name("koma_memory_budget_in_use_bytes")
                       .Help("Bytes of the memory budget reserved by calls in flight.")
                       .Register(registry)
                       .Add({});
  refused_counter_ = &prometheus::BuildCounter()
                          .Name("koma_memory_budget_refused_total")
                          .Help(
                              "Calls answered RESOURCE_EXHAUSTED because the memory budget "
                              "was full or too small for them.")
                          .Register(registry)
                          .Add({});
}

bool MemoryBudget::TryTake(int64_t bytes) {
  int64_t used = in_use_.load(std::memory_order_relaxed);
  do {
    if (bytes > capacity_ - used) return false;
  } while (!in_use_.compare_exchange_weak(used, used + bytes, std::memory_order_relaxed));
  if (in_use_gauge_ != nullptr) in_use_gauge_->Increment(static_cast<double>(bytes));
  return true;
}

void MemoryBudget::Give(int64_t bytes) {
  in_use_.fetch_sub(bytes, std::memory_order_relaxed);
  if (in_use_gauge_ != nullptr) in_use_gauge_->Decrement(static_cast<double>(bytes));
}

absl::Status MemoryBudget::Refusal(int64_t bytes, const char* what) {
  refused_.fetch_add(1, std::memory_order_relaxed);
  if (refused_counter_ != nullptr) refused_counter_->Increment();
  const std::string& budget = name_;
  if (bytes > capacity_) {
    return absl::ResourceExhaustedError(absl::StrCat(budget, ": ", what, " needs ", MiB(bytes),
                                                     ", more than the whole budget; send a smaller "
                                                     "request or raise --max_memory_mb"));
  }
  return absl::ResourceExhaustedError(
      absl::StrCat(budget, ": ", what, " needs ", MiB(bytes), ", ", MiB(in_use()), " of ",
                   MiB(capacity_), " are held by calls in flight; retry with backoff"));
}

namespace {

// This process' cgroup v2 path ("/system.slice/x.service"), from /proc/self/cgroup's "0::" line.
std::string CgroupV2Path(const std::string& root) {
  std::ifstream in(root + "/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    absl::string_view rest = line;
    if (absl::ConsumePrefix(&rest, "0::")) return rest == "/" ? "" : std::string(rest);
  }
  return "";
}

}  // namespace

int64_t DefaultMemoryBudgetMb(const std::string& root) {
  // The process' own cgroup first (systemd units), then the root of the mounted hierarchy
  // (a container sees its own cgroup there), then cgroup v1.
  int64_t limit = CgroupLimit(root + "/sys/fs/cgroup" + CgroupV2Path(root) + "/memory.max");
  if (limit == 0) limit = CgroupLimit(root + "/sys/fs/cgroup/memory.max");
  if (limit == 0) limit = CgroupLimit(root + "/sys/fs/cgroup/memory/memory.limit_in_bytes");
  const int64_t total = MemTotal(root);
  if (limit == 0 || (total > 0 && total < limit)) limit = total;
  if (limit <= 0) return 1024;  // nothing readable: 1 GiB
  return std::max<int64_t>(64, limit / 4 * 3 / kMiB);
}

}  // namespace koma::server
