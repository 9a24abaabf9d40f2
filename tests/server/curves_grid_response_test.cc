// The RetimeCurves wire encoder's film-grid fields (DrawingTiming.drawing_start_grid,
// RetimeCurvesResponse.timing_fps and key_grid_frames, written after the curves) against
// FillCurvesResponse + SerializeToString: on core results with edge values in those fields,
// and on real grid answers (30 .. 240 fps); whole (WriteTo) and in slices of every small size
// (EncodeInSlices), where the tail must come last, once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/split_mix64.h"
#include "koma/v1/retime.pb.h"
#include "server/curves_request.h"
#include "server/curves_response.h"
#include "server/request_limits.h"
#include "tests/server/curves_request_builder.h"
#include "tests/server/curves_response_bytes.h"
#include "tests/server/in_process_server.h"

namespace koma::server {
namespace {

using ::koma::testing::Encoded;
using ::koma::testing::Serialised;

// EncodeInSlices on a copy of `result` at `slice_bytes`, joined.
std::string Sliced(const CurveSet& set, const KomaUchiResult& result, size_t slice_bytes,
                   size_t* slice_count) {
  KomaUchiResult copy = result;
  const CurvesResponseEncoder encoder(set, copy);
  const std::vector<grpc::Slice> slices = EncodeInSlices(encoder, copy, slice_bytes);
  std::string joined;
  for (const grpc::Slice& s : slices) {
    joined.append(reinterpret_cast<const char*>(s.begin()), s.size());
  }
  *slice_count = slices.size();
  return joined;
}

void ExpectAllEncodingsEqual(const CurveSet& set, const KomaUchiResult& result,
                             const std::string& context) {
  const std::string want = Serialised(set, result);
  ASSERT_EQ(Encoded(set, result), want) << context;
  for (size_t slice_bytes : {size_t{0}, size_t{1}, size_t{2}, size_t{7}, size_t{40}, size_t{300},
                             size_t{1} << 20}) {
    size_t slices = 0;
    ASSERT_EQ(Sliced(set, result, slice_bytes, &slices), want)
        << context << ", slices of " << slice_bytes << " bytes (" << slices << ")";
    if (slice_bytes <= 1) {  // every part but the tail a slice of its own, the late tail too
      const CurvesResponseEncoder encoder(set, result);
      const size_t head = encoder.head_size() > 0 ? 1 : 0;
      const size_t late = encoder.late_tail().empty() ? 0 : 1;
      EXPECT_EQ(slices, std::max<size_t>(1, head + set.curves.size()) + late) << context;
    }
  }
}

// A hand-made answer: two timings with grid starts (0, small, multi-byte, negative, the
// extremes), key grid frames, and each timing_fps the encoder must write as protobuf does.
TEST(CurvesGridResponseTest, GridFieldsEncodeAsTheMessages) {
  const double fps_values[] = {24.0, 0.0, -0.0, 1000.0, 1e-300,
                               std::numeric_limits<double>::quiet_NaN(),
                               std::numeric_limits<double>::denorm_min()};
  const std::vector<std::vector<int>> grid_lists = {
      {},
      {0},
      {0, 3, 6, 9, 12, 24},
      {0, 127, 128, 16383, 16384, 2097152, std::numeric_limits<int>::max()},
      {-1, std::numeric_limits<int>::min(), 5}};
  for (double fps : fps_values) {
    for (size_t a = 0; a < grid_lists.size(); ++a) {
      for (int curves = 0; curves <= 3; ++curves) {
        CurveSet set;
        KomaUchiResult result;
        result.key_frames = {0, 5, 30};
        result.key_grid_frames = grid_lists[(a + 1) % grid_lists.size()];
        result.timing_fps = fps;
        for (int t = 0; t < 2; ++t) {
          DrawingTiming timing;
          timing.frames_per_drawing = 3 - t;
          timing.drawing_of_frame = {0, 0, 1, 1, 2};
          timing.source_frame = {0.0, 0.0, 1.25, 1.25, 4.0};
          timing.drawing_start = {0, 2, 4};
          timing.drawing_start_grid = grid_lists[(a + static_cast<size_t>(t)) % grid_lists.size()];
          timing.drawing_time = {0.0, 1.25, 3.75};  // not on the wire
          timing.drawing_tau = {0.0, 1.0, 3.0};
          result.timings.push_back(timing);
        }
        for (int c = 0; c < curves; ++c) {
          Curve curve;
          curve.id = "Param" + std::to_string(c);
          set.curves.push_back(curve);
          RetimedCurve out;
          out.timing = c % 2;
          out.values = {0.5, 0.5, -1.0, -1.0, 2.0};
          out.steps = {{0.0, 0.5}, {1.25, -1.0}, {3.75, 2.0}, {4.0, 2.0}};
          out.hold_histogram = {{1, 1}, {2, 2}};
          result.curves.push_back(out);
        }
        ExpectAllEncodingsEqual(set, result,
                                "timing_fps " + std::to_string(fps) + ", lists " +
                                    std::to_string(a) + ", " + std::to_string(curves) +
                                    " curves");
        if (HasFatalFailure()) return;
      }
    }
  }
}

// The tail (timing_fps, key_grid_frames) follows the last curve: the message's field order.
TEST(CurvesGridResponseTest, TailComesAfterTheCurves) {
  CurveSet set;
  set.curves.emplace_back();
  set.curves.back().id = "A";
  KomaUchiResult result;
  result.curves.emplace_back();
  result.timing_fps = 24.0;
  result.key_grid_frames = {0, 24};
  const std::string bytes = Encoded(set, result);
  // curves (field 3): "\x1a" len; timing_fps (4, fixed64): "\x21" + 8 bytes; key_grid_frames
  // (5, packed): "\x2a\x02\x00\x18".
  ASSERT_GE(bytes.size(), 13u);
  EXPECT_EQ(bytes.substr(bytes.size() - 13, 1), "\x21");
  EXPECT_EQ(bytes.substr(bytes.size() - 4), std::string("\x2a\x02\x00\x18", 4));
  EXPECT_EQ(bytes[0], '\x1a');
  EXPECT_EQ(bytes, Serialised(set, result));
}

// Real answers on the default 24 fps grid at several rates, with per-curve n (several
// timings), overrides and large clips: the service's bytes are the messages'.
TEST(CurvesGridResponseTest, GridAnswersEncodeAsTheMessages) {
  SplitMix64 rng(1724);
  const double rates[] = {25.0, 30.0, 60.0, 120.0, 240.0, 29.97, 12.0};
  RequestLimits limits;
  int with_grid_starts = 0;
  for (int i = 0; i < 150; ++i) {
    v1::RetimeCurvesRequest request;
    v1::CurveSet* set = request.mutable_curves();
    const double fps = rates[i % std::size(rates)];
    const int frames = rng.OneIn(10) ? rng.Int(1000, 4000) : rng.Int(static_cast<int>(fps), 400);
    set->set_fps(fps);
    set->set_frame_count(frames);
    const int curves = rng.Int(1, 6);
    for (int c = 0; c < curves; ++c) {
      v1::Curve* curve = set->add_curves();
      curve->set_id("P" + std::to_string(c));
      if (rng.OneIn(4)) {
        for (int f = 0; f < frames; ++f) curve->add_samples(rng.Unit());
      } else {
        ::koma::testing::AddRandomKeyframes(rng, frames, 1, 20, 4, curve);
      }
      if (rng.OneIn(3)) {
        v1::CurveOverride* own = request.add_curve_overrides();
        own->set_curve_id(curve->id());
        own->set_frames_per_drawing(rng.Int(1, 5));
      }
    }
    if (rng.OneIn(2)) request.set_frames_per_drawing(rng.Int(1, 4));
    if (rng.OneIn(3)) request.set_tame(1.0 + rng.Unit());
    if (rng.OneIn(3)) request.add_segment_overrides()->set_tsume(1.5);  // segment 0
    CurvesAnswer answer;
    const absl::Status status = RetimeCurvesAnswer(request, limits, &answer);
    ASSERT_TRUE(status.ok()) << "request " << i << ": " << status;
    ASSERT_EQ(answer.result.timing_fps, 24.0) << "request " << i;
    ASSERT_FALSE(answer.result.key_grid_frames.empty());
    with_grid_starts += !answer.result.timings[0].drawing_start_grid.empty();
    ExpectAllEncodingsEqual(answer.set, answer.result, "request " + std::to_string(i));
    if (HasFatalFailure()) return;
    v1::RetimeCurvesResponse response;
    ASSERT_TRUE(HandleRetimeCurves(request, limits, &response).ok());
    ASSERT_EQ(Encoded(answer.set, answer.result), response.SerializeAsString()) << i;
    ASSERT_EQ(response.key_grid_frames_size(), response.key_frames_size()) << i;
  }
  EXPECT_EQ(with_grid_starts, 150);
}

// Through the service, whose answers of 512 KiB and up go out in several slices: a large grid
// answer (60 fps, 20 curves x 7200 frames, two timings, merged key poses; ~1.7 MB) is the
// message's bytes, tail and late tail (key_frames_merged) included.
TEST(CurvesGridResponseTest, LargeGridAnswerThroughTheServiceIsTheMessagesBytes) {
  SplitMix64 rng(60);
  v1::RetimeCurvesRequest request;
  v1::CurveSet* set = request.mutable_curves();
  set->set_fps(60.0);
  set->set_frame_count(7200);
  for (int c = 0; c < 20; ++c) {
    v1::Curve* curve = set->add_curves();
    curve->set_id("P" + std::to_string(c));
    ::koma::testing::AddRandomKeyframes(rng, 7200, 5, 90, 0, curve);
    if (c % 4 == 1) {
      v1::CurveOverride* own = request.add_curve_overrides();
      own->set_curve_id(curve->id());
      own->set_frames_per_drawing(2);
    }
  }
  v1::RetimeCurvesResponse want;
  ASSERT_TRUE(HandleRetimeCurves(request, RequestLimits{}, &want).ok());
  ASSERT_EQ(want.timing_fps(), 24.0);
  ASSERT_EQ(want.timings_size(), 2);
  ASSERT_GT(want.key_frames_merged_size(), 0);
  const std::string want_bytes = want.SerializeAsString();
  ASSERT_GT(want_bytes.size(), size_t{3} << 19);  // over three 512 KiB slices
  koma::testing::InProcessServer server;
  std::string got;
  const grpc::Status status = koma::testing::RawUnaryCall(
      server, "/koma.v1.Retime/RetimeCurves", request.SerializeAsString(), &got);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_TRUE(got == want_bytes) << got.size() << " bytes, want " << want_bytes.size();
}

}  // namespace
}  // namespace koma::server
