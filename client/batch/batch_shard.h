// `koma batch --shard K/N`: a render farm splits one batch into N tasks (a Kubernetes Indexed
// Job, a Slurm job array, an OpenCue layer's frames, a Flamenco job's tasks), each running the
// same command line with its own index K; together they do every clip exactly once.
#ifndef KOMA_CLIENT_BATCH_BATCH_SHARD_H_
#define KOMA_CLIENT_BATCH_BATCH_SHARD_H_

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "client/batch/batch_inputs.h"

namespace koma::client::batch {

// Task `index` of `count` (0 <= index < count). {0, 1} is the whole batch.
struct Shard {
  int64_t index = 0;
  int64_t count = 1;
  bool whole() const { return count == 1; }
  // "3-of-8": the tag in the names of the task's own manifest and summary.
  std::string Tag() const;
};

// At most this many tasks (a farm's array is far smaller; more would leave most tasks empty).
constexpr int64_t kMaxShardCount = 1000000;

// The shard a clip belongs to among `count`: a hash of its output path below the output folder
// (BatchItem::relative), the one name every task derives alike from the same command line, so
// it depends on that clip alone. Adding or removing a clip moves no other clip; the sizes are
// binomial around total/count (no coordination between tasks). Same on every machine: FNV-1a
// then SplitMix64's finalizer, integers only.
int64_t ShardOf(const std::string& relative, int64_t count);

// The items of `shard`, in their order.
std::vector<BatchItem> SelectShard(const std::vector<BatchItem>& items, const Shard& shard);

// "K/N" as typed after --shard. INVALID_ARGUMENT naming the flag and the value: not two
// integers, N < 1 or > kMaxShardCount, K outside 0..N-1 (the index counts from 0).
absl::StatusOr<Shard> ParseShard(const std::string& text);

// --shard-from-env: the task's index and count from the scheduler's variables, the first of
//   KOMA_SHARD_INDEX (+ KOMA_SHARD_COUNT)          any farm: set them in the task's command
//   JOB_COMPLETION_INDEX (+ KOMA_SHARD_COUNT)      a Kubernetes Indexed Job (count = completions)
//   SLURM_ARRAY_TASK_ID (+ SLURM_ARRAY_TASK_COUNT, SLURM_ARRAY_TASK_MIN, SLURM_ARRAY_TASK_STEP)
//                                                  a Slurm job array: index (ID - MIN) / STEP
// `getenv` is the lookup (std::getenv in koma; a map in tests). INVALID_ARGUMENT naming the
// variable and its value when one is missing, not an integer, or out of range, and when none
// of the index variables is set.
absl::StatusOr<Shard> ShardFromEnvironment(const std::function<const char*(const char*)>& getenv);

// `path` with the shard's tag before its extension: ("out/sum.json", 3 of 8) ->
// "out/sum.3-of-8.json"; "-" and the whole batch's paths unchanged.
std::string ShardedPath(const std::string& path, const Shard& shard);

}  // namespace koma::client::batch

#endif  // KOMA_CLIENT_BATCH_BATCH_SHARD_H_
