#include "client/batch/batch_shard.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"

namespace koma::client::batch {
namespace {

// 64-bit FNV-1a, then SplitMix64's finalizer (Steele, Lea and Flood 2014), so that names
// differing in their last byte spread over every shard, not only over neighbours mod N.
uint64_t NameHash(const std::string& name) {
  uint64_t hash = 1469598103934665603ULL;
  for (unsigned char c : name) {
    hash ^= c;
    hash *= 1099511628211ULL;
  }
  hash = (hash ^ (hash >> 30)) * 0xbf58476d1ce4e5b9ULL;
  hash = (hash ^ (hash >> 27)) * 0x94d049bb133111ebULL;
  return hash ^ (hash >> 31);
}

// A whole decimal number, nothing around it.
bool ParseInt(const std::string& text, int64_t* value) {
  return !text.empty() && text.find_first_of(" \t+") == std::string::npos &&
         absl::SimpleAtoi(text, value);
}

absl::StatusOr<int64_t> ReadVariable(const std::function<const char*(const char*)>& getenv,
                                     const char* name, const std::string& needed_by) {
  const char* value = getenv(name);
  if (value == nullptr) {
    return absl::InvalidArgumentError(
        absl::StrCat("--shard-from-env: ", needed_by, " is set but ", name, " is not"));
  }
  int64_t number = 0;
  if (!ParseInt(value, &number)) {
    return absl::InvalidArgumentError(
        absl::StrCat("--shard-from-env: ", name, "=\"", value, "\" is not an integer"));
  }
  return number;
}

absl::StatusOr<Shard> CheckedShard(int64_t index, int64_t count, const std::string& where) {
  if (count < 1 || count > kMaxShardCount) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": ", count, " tasks: must be 1..", kMaxShardCount));
  }
  if (index < 0 || index >= count) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": task index ", index, " is outside 0..",
                                                   count - 1, " (the index counts from 0)"));
  }
  return Shard{index, count};
}

}  // namespace

std::string Shard::Tag() const { return absl::StrCat(index, "-of-", count); }

int64_t ShardOf(const std::string& relative, int64_t count) {
  return static_cast<int64_t>(NameHash(relative) % static_cast<uint64_t>(count));
}

std::vector<BatchItem> SelectShard(const std::vector<BatchItem>& items, const Shard& shard) {
  std::vector<BatchItem> selected;
  for (const BatchItem& item : items) {
    if (ShardOf(item.relative, shard.count) == shard.index) selected.push_back(item);
  }
  return selected;
}

absl::StatusOr<Shard> ParseShard(const std::string& text) {
  const std::vector<std::string> parts = absl::StrSplit(text, '/');
  int64_t index = 0;
  int64_t count = 0;
  if (parts.size() != 2 || !ParseInt(parts[0], &index) || !ParseInt(parts[1], &count)) {
    return absl::InvalidArgumentError(
        absl::StrCat("--shard ", text, ": want K/N, task K (from 0) of N, such as 0/8 ... 7/8"));
  }
  return CheckedShard(index, count, absl::StrCat("--shard ", text));
}

absl::StatusOr<Shard> ShardFromEnvironment(const std::function<const char*(const char*)>& getenv) {
  for (const char* index_name : {"KOMA_SHARD_INDEX", "JOB_COMPLETION_INDEX"}) {
    if (getenv(index_name) == nullptr) continue;
    absl::StatusOr<int64_t> index = ReadVariable(getenv, index_name, index_name);
    if (!index.ok()) return index.status();
    absl::StatusOr<int64_t> count = ReadVariable(getenv, "KOMA_SHARD_COUNT", index_name);
    if (!count.ok()) return count.status();
    return CheckedShard(
        *index, *count,
        absl::StrCat("--shard-from-env: ", index_name, "=", *index, ", KOMA_SHARD_COUNT=", *count));
  }
  if (getenv("SLURM_ARRAY_TASK_ID") != nullptr) {
    const std::string by = "SLURM_ARRAY_TASK_ID";
    absl::StatusOr<int64_t> id = ReadVariable(getenv, "SLURM_ARRAY_TASK_ID", by);
    if (!id.ok()) return id.status();
    absl::StatusOr<int64_t> count = ReadVariable(getenv, "SLURM_ARRAY_TASK_COUNT", by);
    if (!count.ok()) return count.status();
    absl::StatusOr<int64_t> min = ReadVariable(getenv, "SLURM_ARRAY_TASK_MIN", by);
    if (!min.ok()) return min.status();
    int64_t step = 1;
    if (getenv("SLURM_ARRAY_TASK_STEP") != nullptr) {
      absl::StatusOr<int64_t> read = ReadVariable(getenv, "SLURM_ARRAY_TASK_STEP", by);
      if (!read.ok()) return read.status();
      step = *read;
    }
    const std::string where =
        absl::StrCat("--shard-from-env: SLURM_ARRAY_TASK_ID=", *id, ", SLURM_ARRAY_TASK_MIN=", *min,
                     ", SLURM_ARRAY_TASK_STEP=", step, ", SLURM_ARRAY_TASK_COUNT=", *count);
    if (step < 1 || (*id - *min) % step != 0) {
      return absl::InvalidArgumentError(absl::StrCat(
          where, ": not a task of an evenly stepped array (submit --array=0-", *count - 1, ")"));
    }
    absl::StatusOr<Shard> shard = CheckedShard((*id - *min) / step, *count, where);
    if (!shard.ok()) {
      return absl::InvalidArgumentError(
          absl::StrCat(shard.status().message(),
                       "; an array with gaps cannot be split evenly: submit "
                       "--array=0-",
                       *count - 1));
    }
    return shard;
  }
  return absl::InvalidArgumentError(
      "--shard-from-env: none of KOMA_SHARD_INDEX, JOB_COMPLETION_INDEX (a Kubernetes Indexed "
      "Job) or SLURM_ARRAY_TASK_ID (a Slurm job array) is set");
}

std::string ShardedPath(const std::string& path, const Shard& shard) {
  if (shard.whole() || path == "-") return path;
  const std::filesystem::path p(path);
  const std::string name = p.filename().string();
  const size_t dot = name.rfind('.');  // before the last extension; a leading dot stays
  const std::string tagged =
      dot == std::string::npos || dot == 0
          ? absl::StrCat(name, ".", shard.Tag())
          : absl::StrCat(name.substr(0, dot), ".", shard.Tag(), name.substr(dot));
  return (p.parent_path() / tagged).string();
}

}  // namespace koma::client::batch
