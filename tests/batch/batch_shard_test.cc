// `koma batch --shard K/N`: the shards partition any input list, adding a clip moves only that
// clip, and K/N is read from the flag or the scheduler's environment with named errors.
#include "client/batch/batch_shard.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "tests/testing/status_matchers.h"

namespace koma::client::batch {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

// A clip as DiscoverInputs makes it; only `relative` decides its shard.
BatchItem Item(const std::string& relative) {
  return BatchItem{"/in/" + relative, relative, "/out/" + relative, "", "", "", "", ""};
}

// `count` distinct names shaped like a studio's tree: shot folders, numbered clips.
std::vector<BatchItem> RandomItems(std::mt19937_64& rng, int count) {
  std::set<std::string> names;
  std::uniform_int_distribution<int> folder(0, 40), number(0, 99999), ext(0, 2);
  const char* extensions[] = {".bvh", ".motion3.json", ".csv"};
  while (static_cast<int>(names.size()) < count) {
    names.insert(absl::StrCat("sq", folder(rng), "/sh", folder(rng), "/clip_", number(rng),
                              extensions[ext(rng)]));
  }
  std::vector<BatchItem> items;
  for (const std::string& name : names) items.push_back(Item(name));
  std::shuffle(items.begin(), items.end(), rng);  // the partition must not need sorted input
  return items;
}

// The shard of every item, from running every task K = 0..N-1 as the farm would; fails the
// test if an item is in no shard or in two, or a task reorders its items.
std::map<std::string, int64_t> RunAllTasks(const std::vector<BatchItem>& items, int64_t n) {
  std::map<std::string, int64_t> shard_of;
  for (int64_t k = 0; k < n; ++k) {
    const std::vector<BatchItem> selected = SelectShard(items, Shard{k, n});
    size_t last = 0;
    for (const BatchItem& item : selected) {
      EXPECT_TRUE(shard_of.emplace(item.relative, k).second)
          << item.relative << " is in shards " << shard_of[item.relative] << " and " << k;
      size_t at = last;
      while (at < items.size() && items[at].relative != item.relative) ++at;
      EXPECT_LT(at, items.size()) << "task " << k << " of " << n << " reordered its clips";
      last = at;
    }
  }
  return shard_of;
}

TEST(BatchShardTest, ShardsPartitionRandomListsForEveryCountUpTo64) {
  std::mt19937_64 rng(34);
  for (int trial = 0; trial < 25; ++trial) {
    const int size = std::uniform_int_distribution<int>(0, 200)(rng);
    const std::vector<BatchItem> items = RandomItems(rng, size);
    for (int64_t n = 1; n <= 64; ++n) {
      const std::map<std::string, int64_t> shard_of = RunAllTasks(items, n);
      ASSERT_EQ(shard_of.size(), items.size()) << "trial " << trial << ", N = " << n;
      for (const BatchItem& item : items) {
        ASSERT_EQ(shard_of.count(item.relative), 1u) << item.relative << " in no shard of " << n;
        EXPECT_EQ(shard_of.at(item.relative), ShardOf(item.relative, n));
      }
    }
  }
}

TEST(BatchShardTest, AddingAnInputMovesOnlyThatInput) {
  std::mt19937_64 rng(3434);
  for (int trial = 0; trial < 25; ++trial) {
    const int size = std::uniform_int_distribution<int>(1, 150)(rng);
    std::vector<BatchItem> items = RandomItems(rng, size + 1);
    const BatchItem added = items.back();
    items.pop_back();
    std::vector<BatchItem> grown = items;
    grown.insert(grown.begin() + std::uniform_int_distribution<int>(0, size)(rng), added);
    for (int64_t n = 1; n <= 64; ++n) {
      const std::map<std::string, int64_t> before = RunAllTasks(items, n);
      std::map<std::string, int64_t> after = RunAllTasks(grown, n);
      ASSERT_EQ(after.count(added.relative), 1u);
      after.erase(added.relative);
      EXPECT_EQ(after, before) << "adding " << added.relative << " moved other clips (N = " << n
                               << ")";
    }
  }
}

TEST(BatchShardTest, ShardSizesStayNearTheMean) {
  // 6,400 clips over 64 tasks: binomial(6400, 1/64), mean 100, sd ~9.9; every task within
  // 5 sd. Names differing only in a digit (clip_0001 ... ) must spread, not cluster.
  std::vector<BatchItem> items;
  for (int i = 0; i < 6400; ++i) items.push_back(Item(absl::StrCat("shot/clip_", i, ".bvh")));
  for (int64_t n : {2, 7, 64}) {
    const double mean = 6400.0 / n;
    for (int64_t k = 0; k < n; ++k) {
      const double size = static_cast<double>(SelectShard(items, Shard{k, n}).size());
      EXPECT_NEAR(size, mean, 5 * std::sqrt(mean)) << "task " << k << " of " << n;
    }
  }
}

TEST(BatchShardTest, OneTaskIsTheWholeBatch) {
  std::mt19937_64 rng(1);
  const std::vector<BatchItem> items = RandomItems(rng, 50);
  const std::vector<BatchItem> all = SelectShard(items, Shard{0, 1});
  ASSERT_EQ(all.size(), items.size());
  for (size_t i = 0; i < items.size(); ++i) EXPECT_EQ(all[i].relative, items[i].relative);
}

TEST(BatchShardTest, ParsesKOfN) {
  absl::StatusOr<Shard> shard = ParseShard("3/8");
  ASSERT_THAT(shard.status(), IsOk());
  EXPECT_EQ(shard->index, 3);
  EXPECT_EQ(shard->count, 8);
  EXPECT_EQ(shard->Tag(), "3-of-8");
  EXPECT_THAT(ParseShard("0/1").status(), IsOk());
  EXPECT_THAT(ParseShard("8/8").status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("--shard 8/8: task index 8 is outside 0..7 (the index counts "
                                 "from 0)")));
  EXPECT_THAT(ParseShard("-1/8").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("outside 0..7")));
  EXPECT_THAT(ParseShard("0/0").status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("--shard 0/0: 0 tasks: must be 1..1000000")));
  for (const char* bad : {"", "3", "3/", "/8", "a/8", "3/8/1", "3 /8", "3/+8", "1.5/4"}) {
    EXPECT_THAT(ParseShard(bad).status(),
                StatusIs(absl::StatusCode::kInvalidArgument,
                         HasSubstr(absl::StrCat("--shard ", bad, ": want K/N"))))
        << bad;
  }
}

// A fake environment for ShardFromEnvironment.
class Environment {
 public:
  explicit Environment(std::initializer_list<std::pair<const char*, const char*>> values) {
    for (const auto& [name, value] : values) values_[name] = value;
  }
  absl::StatusOr<Shard> Read() const {
    return ShardFromEnvironment([this](const char* name) -> const char* {
      auto it = values_.find(name);
      return it == values_.end() ? nullptr : it->second.c_str();
    });
  }

 private:
  std::map<std::string, std::string> values_;
};

void ExpectShard(const Environment& env, int64_t index, int64_t count) {
  absl::StatusOr<Shard> shard = env.Read();
  ASSERT_THAT(shard.status(), IsOk());
  EXPECT_EQ(shard->index, index);
  EXPECT_EQ(shard->count, count);
}

TEST(BatchShardTest, ReadsTheSchedulersVariables) {
  ExpectShard(Environment({{"KOMA_SHARD_INDEX", "2"}, {"KOMA_SHARD_COUNT", "5"}}), 2, 5);
  ExpectShard(Environment({{"JOB_COMPLETION_INDEX", "0"}, {"KOMA_SHARD_COUNT", "3"}}), 0, 3);
  // KOMA_SHARD_INDEX wins over the scheduler's own (a wrapper re-splitting a task).
  ExpectShard(Environment({{"KOMA_SHARD_INDEX", "1"},
                           {"KOMA_SHARD_COUNT", "2"},
                           {"SLURM_ARRAY_TASK_ID", "7"},
                           {"SLURM_ARRAY_TASK_COUNT", "8"},
                           {"SLURM_ARRAY_TASK_MIN", "0"}}),
              1, 2);
  // sbatch --array=1-8: IDs 1..8, index = ID - MIN.
  ExpectShard(Environment({{"SLURM_ARRAY_TASK_ID", "8"},
                           {"SLURM_ARRAY_TASK_COUNT", "8"},
                           {"SLURM_ARRAY_TASK_MIN", "1"},
                           {"SLURM_ARRAY_TASK_MAX", "8"}}),
              7, 8);
  // sbatch --array=10-40:10: IDs 10, 20, 30, 40.
  ExpectShard(Environment({{"SLURM_ARRAY_TASK_ID", "30"},
                           {"SLURM_ARRAY_TASK_COUNT", "4"},
                           {"SLURM_ARRAY_TASK_MIN", "10"},
                           {"SLURM_ARRAY_TASK_STEP", "10"}}),
              2, 4);
}

TEST(BatchShardTest, NamesTheVariableThatIsWrong) {
  EXPECT_THAT(Environment{}.Read().status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("none of KOMA_SHARD_INDEX, JOB_COMPLETION_INDEX")));
  EXPECT_THAT(Environment({{"JOB_COMPLETION_INDEX", "4"}}).Read().status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("JOB_COMPLETION_INDEX is set but KOMA_SHARD_COUNT is not")));
  EXPECT_THAT(Environment({{"KOMA_SHARD_INDEX", "x1"}, {"KOMA_SHARD_COUNT", "2"}}).Read().status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("KOMA_SHARD_INDEX=\"x1\" is not an integer")));
  EXPECT_THAT(
      Environment({{"JOB_COMPLETION_INDEX", "4"}, {"KOMA_SHARD_COUNT", "4"}}).Read().status(),
      StatusIs(absl::StatusCode::kInvalidArgument,
               HasSubstr("JOB_COMPLETION_INDEX=4, KOMA_SHARD_COUNT=4: task index 4 is "
                         "outside 0..3")));
  EXPECT_THAT(
      Environment({{"SLURM_ARRAY_TASK_ID", "3"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}).Read().status(),
      StatusIs(absl::StatusCode::kInvalidArgument,
               HasSubstr("SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_MIN is not")));
  // sbatch --array=1,3,9: three tasks, IDs with gaps.
  EXPECT_THAT(Environment({{"SLURM_ARRAY_TASK_ID", "9"},
                           {"SLURM_ARRAY_TASK_COUNT", "3"},
                           {"SLURM_ARRAY_TASK_MIN", "1"}})
                  .Read()
                  .status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("an array with gaps cannot be split evenly: submit "
                                 "--array=0-2")));
  EXPECT_THAT(Environment({{"SLURM_ARRAY_TASK_ID", "15"},
                           {"SLURM_ARRAY_TASK_COUNT", "4"},
                           {"SLURM_ARRAY_TASK_MIN", "10"},
                           {"SLURM_ARRAY_TASK_STEP", "10"}})
                  .Read()
                  .status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("not a task of an evenly stepped array")));
}

TEST(BatchShardTest, TaggedPathsAreTheTasksOwn) {
  const Shard three_of_eight{3, 8};
  EXPECT_EQ(ShardedPath("out/summary.json", three_of_eight), "out/summary.3-of-8.json");
  EXPECT_EQ(ShardedPath(".koma-batch.json", three_of_eight), ".koma-batch.3-of-8.json");
  EXPECT_EQ(ShardedPath("out/summary", three_of_eight), "out/summary.3-of-8");
  EXPECT_EQ(ShardedPath("out.d/.hidden", three_of_eight), "out.d/.hidden.3-of-8");
  EXPECT_EQ(ShardedPath("-", three_of_eight), "-");
  EXPECT_EQ(ShardedPath("out/summary.json", Shard{0, 1}), "out/summary.json");
}

// Pinned so that a change of hash (which would send clips to other tasks on a farm running
// two koma versions side by side) is a decision, not an accident. The values come from an
// independent Python implementation (FNV-1a 64, SplitMix64's finalizer, mod N), which the
// end-to-end test (tests/e2e/batch_shard_e2e_test.sh) also checks every task's clips against.
TEST(BatchShardTest, ShardOfIsPinned) {
  EXPECT_EQ(ShardOf("pitch.bvh", 1), 0);
  std::map<std::string, int64_t> pinned;
  for (const char* name : {"pitch.bvh", "g00/clip_0000.bvh", "a/b.motion3.json"}) {
    pinned[name] = ShardOf(name, 64);
  }
  EXPECT_EQ(pinned, (std::map<std::string, int64_t>{
                        {"pitch.bvh", 32}, {"g00/clip_0000.bvh", 29}, {"a/b.motion3.json", 62}}));
}

}  // namespace
}  // namespace koma::client::batch
