// The server-wide memory budget (server/memory_budget.h): reservations, refusals and their
// messages, its metrics, the default from cgroup limits and /proc/meminfo, and a real server
// that answers RESOURCE_EXHAUSTED naming the budget when a call does not fit.
#include "server/memory_budget.h"

#include <gmock/gmock.h>
#include <google/protobuf/descriptor.h>
#include <gtest/gtest.h>
#include <prometheus/registry.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "server/call_footprint.h"
#include "tests/server/in_process_server.h"
#include "tests/server/request_builder.h"

namespace koma::server {
namespace {

using ::testing::HasSubstr;

constexpr int64_t kMiB = 1024 * 1024;

TEST(MemoryBudgetTest, ReservationsAddUpAndAreGivenBackWhenDestroyed) {
  MemoryBudget budget(100);
  {
    absl::StatusOr<MemoryBudget::Reservation> a = budget.Reserve(60, "a");
    ASSERT_TRUE(a.ok());
    EXPECT_EQ(budget.in_use(), 60);
    absl::StatusOr<MemoryBudget::Reservation> b = budget.Reserve(40, "b");
    ASSERT_TRUE(b.ok());
    EXPECT_EQ(budget.in_use(), 100);
    MemoryBudget::Reservation moved = *std::move(a);
    EXPECT_EQ(budget.in_use(), 100);  // moving does not give anything back
  }
  EXPECT_EQ(budget.in_use(), 0);
  EXPECT_EQ(budget.refused(), 0);
}

TEST(MemoryBudgetTest, RefusesWhatDoesNotFitNamingTheBudgetAndWhatIsInUse) {
  MemoryBudget budget(512 * kMiB, "memory budget (--max_memory_mb=512)");
  absl::StatusOr<MemoryBudget::Reservation> held = budget.Reserve(400 * kMiB, "first");
  ASSERT_TRUE(held.ok());
  const absl::StatusOr<MemoryBudget::Reservation> refused = budget.Reserve(200 * kMiB, "second");
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(refused.status().message(),
            "memory budget (--max_memory_mb=512): second needs 200 MiB, 400 MiB of 512 MiB are "
            "held by calls in flight; retry with backoff");
  EXPECT_EQ(budget.in_use(), 400 * kMiB);  // a refusal takes nothing
  EXPECT_EQ(budget.refused(), 1);
}

TEST(MemoryBudgetTest, ACallLargerThanTheWholeBudgetIsToldSo) {
  MemoryBudget budget(64 * kMiB);
  const absl::StatusOr<MemoryBudget::Reservation> refused = budget.Reserve(65 * kMiB, "this call");
  ASSERT_FALSE(refused.ok());
  EXPECT_THAT(refused.status().message(),
              HasSubstr("this call needs 65 MiB, more than the whole budget"));
}

TEST(MemoryBudgetTest, ResizeGrowsWhenItFitsAndShrinksAlways) {
  MemoryBudget budget(100);
  absl::StatusOr<MemoryBudget::Reservation> r = budget.Reserve(10, "r");
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->Resize(90, "r").ok());
  EXPECT_EQ(budget.in_use(), 90);
  const absl::Status too_big = r->Resize(101, "r");
  EXPECT_EQ(too_big.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(r->bytes(), 90);  // unchanged
  EXPECT_EQ(budget.in_use(), 90);
  EXPECT_TRUE(r->Resize(5, "r").ok());
  EXPECT_EQ(budget.in_use(), 5);
  r->Release();
  EXPECT_EQ(budget.in_use(), 0);
}

TEST(MemoryBudgetTest, WithoutABudgetAReservationAlwaysFits) {
  MemoryBudget::Reservation none;
  EXPECT_FALSE(none.budgeted());
  EXPECT_TRUE(none.Resize(int64_t{1} << 50, "x").ok());
}

// Threads racing for a small budget never hold more than it together, and leave it empty.
TEST(MemoryBudgetTest, ConcurrentReservationsNeverExceedTheCapacity) {
  MemoryBudget budget(1000);
  std::atomic<int64_t> held{0};
  std::atomic<int64_t> peak{0};
  std::atomic<int> granted{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 5000; ++i) {
        const int64_t bytes = 1 + (t * 131 + i * 17) % 400;
        absl::StatusOr<MemoryBudget::Reservation> r = budget.Reserve(bytes, "x");
        if (!r.ok()) continue;
        granted.fetch_add(1);
        const int64_t now = held.fetch_add(bytes) + bytes;
        int64_t seen = peak.load();
        while (now > seen && !peak.compare_exchange_weak(seen, now)) {
        }
        held.fetch_sub(bytes);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_LE(peak.load(), 1000);
  EXPECT_GT(granted.load(), 0);
  EXPECT_EQ(budget.in_use(), 0);
}

double Value(const prometheus::Registry& registry, const std::string& name) {
  for (const prometheus::MetricFamily& family : registry.Collect()) {
    if (family.name != name) continue;
    const prometheus::ClientMetric& metric = family.metric.at(0);
    return family.type == prometheus::MetricType::Gauge ? metric.gauge.value : metric.counter.value;
  }
  ADD_FAILURE() << name << " not registered";
  return -1;
}

TEST(MemoryBudgetTest, MetricsShowTheCapacityWhatIsInUseAndRefusals) {
  prometheus::Registry registry;
  MemoryBudget budget(1000);
  budget.ExportMetrics(registry);
  EXPECT_EQ(Value(registry, "koma_memory_budget_bytes"), 1000);
  absl::StatusOr<MemoryBudget::Reservation> r = budget.Reserve(300, "r");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(Value(registry, "koma_memory_budget_in_use_bytes"), 300);
  EXPECT_FALSE(budget.Reserve(701, "s").ok());
  EXPECT_EQ(Value(registry, "koma_memory_budget_refused_total"), 1);
  r->Release();
  EXPECT_EQ(Value(registry, "koma_memory_budget_in_use_bytes"), 0);
}

// A fake root with /proc and /sys/fs/cgroup files.
class DefaultBudgetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = std::filesystem::path(::testing::TempDir()) /
            ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::remove_all(root_);
    Write("proc/meminfo", "MemTotal:       16384000 kB\nMemFree:        1000 kB\n");
  }
  void Write(const std::string& path, const std::string& text) {
    const std::filesystem::path file = root_ / path;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << text;
  }
  std::string root() const { return root_.string(); }

  std::filesystem::path root_;
};

TEST_F(DefaultBudgetTest, ThreeQuartersOfMemTotalWithoutACgroupLimit) {
  EXPECT_EQ(DefaultMemoryBudgetMb(root()), 16384000LL * 1024 / 4 * 3 / kMiB);
  Write("sys/fs/cgroup/memory.max", "max\n");
  EXPECT_EQ(DefaultMemoryBudgetMb(root()), 16384000LL * 1024 / 4 * 3 / kMiB);
}

TEST_F(DefaultBudgetTest, ThreeQuartersOfTheContainersCgroupV2Limit) {
  Write("sys/fs/cgroup/memory.max", "1073741824\n");
  EXPECT_EQ(DefaultMemoryBudgetMb(root()), 768);
}

TEST_F(DefaultBudgetTest, TheProcessOwnCgroupComesFirst) {
  Write("proc/self/cgroup", "0::/system.slice/koma.service\n");
  Write("sys/fs/cgroup/system.slice/koma.service/memory.max", "536870912\n");
  Write("sys/fs/cgroup/memory.max", "max\n");
  EXPECT_EQ(DefaultMemoryBudgetMb(root()), 384);
}

TEST_F(DefaultBudgetTest, CgroupV1LimitAndItsNoLimitValue) {
  Write("sys/fs/cgroup/memory/memory.limit_in_bytes", "2147483648\n");
  EXPECT_EQ(DefaultMemoryBudgetMb(root()), 1536);
  Write("sys/fs/cgroup/memory/memory.limit_in_bytes", "9223372036854771712\n");
  EXPECT_EQ(DefaultMemoryBudgetMb(root()), 16384000LL * 1024 / 4 * 3 / kMiB);
}

TEST_F(DefaultBudgetTest, ALimitAboveTheMachinesMemoryIsTheMachines) {
  Write("sys/fs/cgroup/memory.max", "1099511627776\n");  // 1 TiB
  EXPECT_EQ(DefaultMemoryBudgetMb(root()), 16384000LL * 1024 / 4 * 3 / kMiB);
}

TEST(CallFootprintTest, SkeletalCountsValuesPositionsAndTheReturnedMotion) {
  const v1::RetimeSkeletalRequest request = testing::MakeSkeletalRequest(100);  // 12 channels
  RequestLimits limits;
  const int64_t with_motion = ExpectedFootprint(request, 0, limits);
  // 1,200 values (8 B), 100 x 3 joints x 3 positions (8 B), the motion again, 64 B per frame.
  EXPECT_EQ(with_motion, 64 * 1024 + 1200 * 8 + 900 * 8 + 1200 * 8 + 100 * 64);
  v1::RetimeSkeletalRequest without = request;
  without.set_return_motion(false);
  EXPECT_EQ(ExpectedFootprint(without, 0, limits), with_motion - 1200 * 8);
}

TEST(CallFootprintTest, ClaimedCountsAreCappedByMaxValues) {
  v1::RetimeCurvesRequest request;
  request.mutable_curves()->set_frame_count(2'000'000'000);
  request.mutable_curves()->add_curves();
  RequestLimits limits;
  limits.max_values = 1000;
  EXPECT_EQ(ExpectedFootprint(request, 10, limits), 64 * 1024 + 10 + 2 * 1000 * 8 + 1000 * 64);
}

// The format table's request fields (formats/format_table.h) are the proto's file fields:
// bytes in a oneof, so the budget finds a file request's format by the field that is set.
TEST(CallFootprintTest, TheFormatTablesRequestFieldsAreTheProtosFileFields) {
  const google::protobuf::DescriptorPool* pool = google::protobuf::DescriptorPool::generated_pool();
  for (const formats::FormatRow& row : formats::FormatTable()) {
    for (const formats::RequestField& carried : row.request_fields) {
      const std::string message = "koma.v1." + std::string(carried.message);
      const google::protobuf::Descriptor* descriptor = pool->FindMessageTypeByName(message);
      ASSERT_NE(descriptor, nullptr) << message;
      const google::protobuf::FieldDescriptor* field =
          descriptor->FindFieldByName(std::string(carried.field));
      ASSERT_NE(field, nullptr) << message << "." << carried.field;
      EXPECT_EQ(field->type(), google::protobuf::FieldDescriptor::TYPE_BYTES) << field->name();
      EXPECT_NE(field->containing_oneof(), nullptr) << field->name();
    }
  }
  // The curve requests' `input` files, each at its row's cost.
  v1::RetimeCurvesRequest curves;
  curves.set_spine_json("{}");
  EXPECT_EQ(CurveFileKind(curves), formats::FormatId::kSpine);
  curves.set_csv_text("frame,a");
  EXPECT_EQ(CurveFileKind(curves), formats::FormatId::kCsv);
  v1::LipBlinkRequest lip_blink;
  EXPECT_EQ(CurveFileKind(lip_blink), formats::FormatId::kMotion3);  // no file: the default
  lip_blink.set_spine_json("{}");
  EXPECT_EQ(CurveFileKind(lip_blink), formats::FormatId::kSpine);
}

// Each file format at its own cost per byte (docs/reliability.md, "Memory per format").
TEST(CallFootprintTest, FilesAreCountedAtTheirFormatsCostPerByte) {
  constexpr int64_t kFixed = 64 * 1024;
  EXPECT_EQ(FileParseFootprint(1000, formats::FormatId::kSpine), kFixed + 24 * 1000);
  EXPECT_EQ(FileParseFootprint(1000, formats::FormatId::kMotion3), kFixed + 28 * 1000);
  EXPECT_EQ(FileParseFootprint(1000, formats::FormatId::kAudio), kFixed + 4 * 1000);
  v1::RetimeCurvesRequest spine;
  spine.set_spine_json(std::string(1000, ' '));
  v1::RetimeCurvesRequest csv;
  csv.set_csv_text(std::string(1000, ' '));
  EXPECT_GT(ExpectedFootprint(spine, 1000, RequestLimits()),
            ExpectedFootprint(csv, 1000, RequestLimits()));
  v1::LipBlinkRequest voice;
  voice.set_audio(std::string(1000, '\0'));
  EXPECT_EQ(ExpectedFootprint(voice, 1000, RequestLimits()), kFixed + 4 * 1000);
}

// glTF: its JSON's structure at 72 per byte, its bytes (buffers, data URIs) at 3.
TEST(CallFootprintTest, GltfCountsItsJsonStructureNotItsEmbeddedData) {
  const std::string structure = R"({"asset":{"version":"2.0"},"buffers":[{"uri":")";
  const std::string data = "data:application/octet-stream;base64," + std::string(100000, 'A');
  const std::string text = structure + data + R"("}]})";
  const int64_t counted = static_cast<int64_t>(text.size() - data.size() - 2);  // w/o quotes
  EXPECT_EQ(GltfFootprint(text), 64 * 1024 + 3 * static_cast<int64_t>(text.size()) + 72 * counted);
  // A GLB: its JSON chunk, not its BIN chunk.
  const std::string json = R"({"asset":{"version":"2.0"}})";
  std::string glb = "glTF";
  const auto put32 = [&glb](uint32_t v) {
    for (int i = 0; i < 4; ++i) glb.push_back(static_cast<char>(v >> (8 * i)));
  };
  put32(2);
  put32(static_cast<uint32_t>(12 + 8 + json.size() + 8 + 4000));
  put32(static_cast<uint32_t>(json.size()));
  glb += "JSON" + json;
  put32(4000);
  glb += "BIN" + std::string(1, '\0') + std::string(4000, '\0');
  EXPECT_EQ(GltfFootprint(glb), 64 * 1024 + 3 * static_cast<int64_t>(glb.size()) +
                                    72 * static_cast<int64_t>(json.size()));
}

// Through a real server: 16 MiB of calls' budget (32 MiB: a quarter to gRPC, half to calls).
TEST(MemoryBudgetServerTest, ACallThatDoesNotFitIsRefusedNamingTheBudget) {
  ServerConfig config = testing::InProcessServer::Config(2, 20'000'000);
  config.max_memory_mb = 32;
  config.metrics_registry = std::make_shared<prometheus::Registry>();
  testing::InProcessServer server(config);
  ASSERT_NE(server.server().memory_budget(), nullptr);
  EXPECT_EQ(server.server().memory_budget()->capacity(), 16 * kMiB);

  // 20,000 frames x 12 channels: values, positions and motion are 5.3 MiB, within it.
  {
    grpc::ClientContext context;
    testing::SetTestDeadline(context);
    v1::RetimeSkeletalResponse response;
    const grpc::Status status =
        server.stub().RetimeSkeletal(&context, testing::MakeSkeletalRequest(20'000), &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
  }
  // 90,000 frames: ~28 MiB expected, over the 16 MiB.
  grpc::ClientContext context;
  testing::SetTestDeadline(context);
  v1::RetimeSkeletalResponse response;
  const grpc::Status status =
      server.stub().RetimeSkeletal(&context, testing::MakeSkeletalRequest(90'000), &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(),
              HasSubstr("memory budget (--max_memory_mb=32, 16 MiB of it for calls)"));
  EXPECT_THAT(status.error_message(), HasSubstr("more than the whole budget"));
  // The first call's reservation goes back once gRPC has taken its response, which may be just
  // after the client has it: wait for that (bounded).
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (server.server().memory_budget()->in_use() != 0 &&
         std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(server.server().memory_budget()->in_use(), 0);
  EXPECT_EQ(Value(*config.metrics_registry, "koma_memory_budget_refused_total"), 1);
}

TEST(MemoryBudgetServerTest, ANegativeOrTinyBudgetIsRefusedAtStart) {
  ServerConfig config;
  config.address = "";
  config.max_memory_mb = -1;
  EXPECT_THAT(ValidateServerConfig(config).message(), HasSubstr("--max_memory_mb: -1"));
  config.max_memory_mb = 8;
  EXPECT_THAT(ValidateServerConfig(config).message(), HasSubstr("--max_memory_mb: 8 is below 16"));
}

}  // namespace
}  // namespace koma::server
