// server/skeletal_parse: the scan that sizes the value array, and a parse that gives the same
// message as protobuf's own from the same bytes, cut into slices as gRPC receives them.
#include "server/skeletal_parse.h"

#include <gmock/gmock.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/server/in_process_server.h"
#include "tests/server/request_builder.h"
#include "tests/testing/status_matchers.h"

namespace koma::server {
namespace {

using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

// `bytes` as a ByteBuffer of `slice_bytes`-byte slices (gRPC hands a large message over in
// many slices; protobuf's parser then grows a packed array slice by slice).
grpc::ByteBuffer Sliced(const std::string& bytes, size_t slice_bytes) {
  std::vector<grpc::Slice> slices;
  for (size_t at = 0; at < bytes.size(); at += slice_bytes) {
    const size_t n = std::min(slice_bytes, bytes.size() - at);
    slices.emplace_back(bytes.data() + at, n);
  }
  return grpc::ByteBuffer(slices.data(), slices.size());
}

v1::RetimeSkeletalRequest PositionsRequest(int frames, int joints) {
  v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(3);
  v1::SkeletalMotion* motion = request.mutable_motion();
  motion->set_frame_count(frames);
  auto* values = motion->mutable_positions()->mutable_values();  // replaces the channels
  for (int k = 0; k < frames * joints * 3; ++k) values->Add(0.25 * (k % 101) - 7.0);
  request.set_holds(5);
  request.add_joint_weights(1.0);
  return request;
}

TEST(SkeletalParseTest, ScanCountsThePackedValuesOfEitherForm) {
  const v1::RetimeSkeletalRequest channels = koma::testing::MakeSkeletalRequest(10);
  PackedValueCounts counts = ScanPackedValueCounts(Sliced(channels.SerializeAsString(), 7));
  EXPECT_EQ(counts.channels, 120);
  EXPECT_EQ(counts.positions, 0);

  const v1::RetimeSkeletalRequest positions = PositionsRequest(50, 3);
  counts = ScanPackedValueCounts(Sliced(positions.SerializeAsString(), 64));
  EXPECT_EQ(counts.positions, 450);
  EXPECT_EQ(counts.channels, 0);

  EXPECT_EQ(
      ScanPackedValueCounts(Sliced(v1::RetimeSkeletalRequest().SerializeAsString(), 8)).positions,
      0);
}

TEST(SkeletalParseTest, SameMessageAsProtobufsParseAndOneAllocationOfTheArray) {
  const v1::RetimeSkeletalRequest positions = PositionsRequest(2000, 31);  // 1.5 MB
  const v1::RetimeSkeletalRequest channels = koma::testing::MakeSkeletalRequest(5000);
  for (const v1::RetimeSkeletalRequest* original : {&positions, &channels}) {
    const std::string bytes = original->SerializeAsString();
    for (size_t slice : {size_t{1}, size_t{13}, size_t{4096}, bytes.size()}) {
      v1::RetimeSkeletalRequest parsed;
      ASSERT_TRUE(ParseSkeletalRequest(Sliced(bytes, slice), &parsed).ok());
      EXPECT_EQ(parsed.SerializeAsString(), bytes) << "slice " << slice;
      const auto& values = parsed.motion().has_positions() ? parsed.motion().positions().values()
                                                           : parsed.motion().channels().values();
      // Reserved once at the final size; protobuf's own parse ends with up to twice as much.
      EXPECT_EQ(values.Capacity(), values.size()) << "slice " << slice;
    }
  }
}

TEST(SkeletalParseTest, BothFormsAndRepeatedMotionParseAsProtobufDoes) {
  // The oneof twice (the later member wins) and the motion field twice (merged).
  v1::RetimeSkeletalRequest first = PositionsRequest(4, 3);
  v1::RetimeSkeletalRequest second = koma::testing::MakeSkeletalRequest(4);
  second.clear_holds();
  const std::string bytes = first.SerializeAsString() + second.SerializeAsString();
  v1::RetimeSkeletalRequest want;
  ASSERT_TRUE(want.ParseFromString(bytes));
  v1::RetimeSkeletalRequest parsed;
  ASSERT_TRUE(ParseSkeletalRequest(Sliced(bytes, 5), &parsed).ok());
  EXPECT_EQ(parsed.SerializeAsString(), want.SerializeAsString());
}

TEST(SkeletalParseTest, MalformedBytesAreInvalidArgument) {
  const std::string bytes = PositionsRequest(20, 3).SerializeAsString();
  for (size_t cut : {size_t{1}, size_t{9}, bytes.size() / 2, bytes.size() - 1}) {
    v1::RetimeSkeletalRequest parsed;
    EXPECT_THAT(ParseSkeletalRequest(Sliced(bytes.substr(0, cut), 3), &parsed),
                StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("RetimeSkeletalRequest")))
        << "cut at " << cut;
  }
  std::string garbage(300, '\xff');
  v1::RetimeSkeletalRequest parsed;
  EXPECT_EQ(ScanPackedValueCounts(Sliced(garbage, 16)).positions, 0);
  EXPECT_THAT(ParseSkeletalRequest(Sliced(garbage, 16), &parsed),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("protobuf parse failed")));
}

// Through the real service (the raw RetimeSkeletal method): bytes that are no request get
// INVALID_ARGUMENT naming the message, and the server goes on answering.
TEST(SkeletalParseTest, ServerAnswersGarbageBytesWithInvalidArgument) {
  koma::testing::InProcessServer server;
  std::string raw_answer;
  const grpc::Status status = koma::testing::RawUnaryCall(server, "/koma.v1.Retime/RetimeSkeletal",
                                                          std::string(100, '\xff'), &raw_answer);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("koma.v1.RetimeSkeletalRequest"));

  grpc::ClientContext again;
  koma::testing::SetTestDeadline(again);
  v1::RetimeSkeletalResponse answer;
  EXPECT_TRUE(
      server.stub().RetimeSkeletal(&again, koma::testing::MakeSkeletalRequest(10), &answer).ok());
  EXPECT_EQ(answer.source_frames_size(), 10);
}

}  // namespace
}  // namespace koma::server
