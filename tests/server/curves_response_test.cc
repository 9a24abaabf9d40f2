// The RetimeCurves wire encoder (server/curves_response.h) against the message path it
// replaces: FillCurvesResponse + SerializeToString must give the very same bytes, on random
// core results with every field's edge values (empty, zero, negative, -0.0, NaN, long ids,
// lengths of several varint bytes) and on the answers to random valid requests (overrides,
// per-curve n, tame and tsume, dense curves, large curves).
#include "server/curves_response.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/split_mix64.h"
#include "koma/v1/retime.pb.h"
#include "server/curves_request.h"
#include "server/request_limits.h"
#include "tests/server/curves_request_builder.h"
#include "tests/server/curves_response_bytes.h"

namespace koma::server {
namespace {

using ::koma::testing::Encoded;
using ::koma::testing::Serialised;

// An int32 drawn among the values whose encodings differ: 0, small, multi-byte varints,
// negatives (ten bytes) and the extremes.
int EdgeInt(SplitMix64& rng) {
  switch (rng.Int(0, 7)) {
    case 0:
      return 0;
    case 1:
      return rng.Int(1, 127);
    case 2:
      return rng.Int(128, 16383);
    case 3:
      return rng.Int(16384, std::numeric_limits<int>::max());
    case 4:
      return -rng.Int(1, 1000);
    case 5:
      return std::numeric_limits<int>::min();
    case 6:
      return std::numeric_limits<int>::max();
    default:
      return rng.Int(0, 400);
  }
}

// A double drawn among the values proto3 treats differently: +0.0 (left out), -0.0 (kept),
// negatives, NaN, infinities, denormals, ordinary values.
double EdgeDouble(SplitMix64& rng) {
  switch (rng.Int(0, 7)) {
    case 0:
      return 0.0;
    case 1:
      return -0.0;
    case 2:
      return -rng.Unit() * 1e6;
    case 3:
      return std::numeric_limits<double>::quiet_NaN();
    case 4:
      return rng.OneIn(2) ? std::numeric_limits<double>::infinity()
                          : -std::numeric_limits<double>::infinity();
    case 5:
      return std::numeric_limits<double>::denorm_min();
    default:
      return rng.Unit() * 300.0;
  }
}

std::vector<int> EdgeInts(SplitMix64& rng, int count) {
  std::vector<int> values(static_cast<size_t>(count));
  for (int& v : values) v = EdgeInt(rng);
  return values;
}

std::vector<double> EdgeDoubles(SplitMix64& rng, int count) {
  std::vector<double> values(static_cast<size_t>(count));
  for (double& v : values) v = EdgeDouble(rng);
  return values;
}

// 0 most often, else up to `most` (a few large ones make lengths of three varint bytes).
int EdgeCount(SplitMix64& rng, int most) {
  if (rng.OneIn(4)) return 0;
  return rng.OneIn(8) ? rng.Int(most / 2, most) : rng.Int(1, 40);
}

std::string EdgeId(SplitMix64& rng, int c) {
  switch (rng.Int(0, 4)) {
    case 0:
      return "";
    case 1:
      return std::string(static_cast<size_t>(rng.Int(127, 300)), 'x');  // 2-byte length
    case 2:
      return "Param\xc3\xa9" + std::to_string(c);  // UTF-8
    default:
      return "P" + std::to_string(c);
  }
}

// A core result with no regard for what the core could produce: the encoder must copy
// whatever it is given.
void RandomAnswer(SplitMix64& rng, CurveSet* set, KomaUchiResult* result) {
  result->key_frames = EdgeInts(rng, EdgeCount(rng, 3000));
  const int timings = rng.Int(0, 3);
  for (int t = 0; t < timings; ++t) {
    DrawingTiming timing;
    timing.frames_per_drawing = EdgeInt(rng);
    timing.drawing_of_frame = EdgeInts(rng, EdgeCount(rng, 5000));
    timing.source_frame = EdgeDoubles(rng, EdgeCount(rng, 5000));
    timing.drawing_start = EdgeInts(rng, EdgeCount(rng, 5000));
    timing.drawing_tau = EdgeDoubles(rng, EdgeCount(rng, 5000));
    timing.given = rng.OneIn(2);
    result->timings.push_back(timing);
  }
  const int curves = rng.Int(0, 6);
  for (int c = 0; c < curves; ++c) {
    Curve curve;
    curve.id = EdgeId(rng, c);
    set->curves.push_back(curve);
    RetimedCurve out;
    out.timing = EdgeInt(rng);
    out.values = EdgeDoubles(rng, EdgeCount(rng, 20000));
    const int steps = EdgeCount(rng, 8000);
    for (int k = 0; k < steps; ++k) out.steps.push_back({EdgeDouble(rng), EdgeDouble(rng)});
    const int holds = rng.Int(0, 4);
    for (int h = 0; h < holds; ++h) out.hold_histogram[EdgeInt(rng)] = EdgeInt(rng);
    result->curves.push_back(out);
  }
  result->key_merged = EdgeInts(rng, EdgeCount(rng, 300));
  const int groups = rng.OneIn(2) ? 0 : rng.Int(1, 4);
  for (int g = 0; g < groups; ++g) {
    TimingGroupResult group;
    group.name = EdgeId(rng, g);
    group.curves = EdgeInts(rng, EdgeCount(rng, 100));
    group.frames_per_drawing = EdgeInt(rng);
    group.key_frames = EdgeInts(rng, EdgeCount(rng, 300));
    group.key_grid_frames = EdgeInts(rng, EdgeCount(rng, 300));
    group.key_merged = EdgeInts(rng, EdgeCount(rng, 300));
    group.timing = EdgeInt(rng);
    result->groups.push_back(group);
  }
}

TEST(CurvesResponseTest, EmptyAnswerIsNoBytes) {
  const CurveSet set;
  const KomaUchiResult result;
  EXPECT_EQ(CurvesResponseEncoder(set, result).size(), 0u);
  EXPECT_EQ(Encoded(set, result), Serialised(set, result));
}

// A curve with nothing in it still carries its (empty) stepped curve, as the message path
// does: mutable_stepped() makes it present.
TEST(CurvesResponseTest, EmptyCurveKeepsItsSteppedField) {
  CurveSet set;
  set.curves.emplace_back();
  KomaUchiResult result;
  result.curves.emplace_back();
  EXPECT_EQ(Encoded(set, result), std::string("\x1a\x02\x22\x00", 4));
  EXPECT_EQ(Encoded(set, result), Serialised(set, result));
}

TEST(CurvesResponseTest, RandomCoreResultsEncodeAsTheMessages) {
  SplitMix64 rng(20240611);
  for (int i = 0; i < 300; ++i) {
    CurveSet set;
    KomaUchiResult result;
    RandomAnswer(rng, &set, &result);
    ASSERT_EQ(Encoded(set, result), Serialised(set, result)) << "answer " << i;
  }
}

// The slices EncodeInSlices writes, joined, are the bytes WriteTo writes; every slice but the
// last holds at least `slice_bytes` (whole parts only), and each curve's result is freed.
TEST(CurvesResponseTest, SlicesJoinToTheSameBytesAndFreeTheCurves) {
  SplitMix64 rng(99);
  for (int i = 0; i < 100; ++i) {
    CurveSet set;
    KomaUchiResult result;
    RandomAnswer(rng, &set, &result);
    const std::string want = Encoded(set, result);
    const KomaUchiResult before = result;
    const size_t slice_bytes = rng.OneIn(4) ? 0 : static_cast<size_t>(rng.Int(1, 400000));
    const CurvesResponseEncoder encoder(set, result);
    const std::vector<grpc::Slice> slices = EncodeInSlices(encoder, result, slice_bytes);
    // The late tail (fields 20-21), when there is one, is a slice of its own after the tail.
    const size_t late = encoder.late_tail().empty() ? 0 : 1;
    std::string joined;
    for (size_t k = 0; k < slices.size(); ++k) {
      joined.append(reinterpret_cast<const char*>(slices[k].begin()), slices[k].size());
      if (k + 1 + late < slices.size()) {
        EXPECT_GE(slices[k].size(), slice_bytes) << "answer " << i << ", slice " << k;
      }
    }
    ASSERT_EQ(joined, want) << "answer " << i << ", " << slices.size() << " slices";
    // A slice is closed as soon as it holds slice_bytes, and never empty while parts remain.
    size_t want_slices = 1;
    size_t open_bytes = encoder.head_size();
    for (size_t c = 0; c < encoder.curve_count(); ++c) {
      if (open_bytes > 0 && open_bytes >= slice_bytes) {
        ++want_slices;
        open_bytes = 0;
      }
      open_bytes += encoder.curve_size(c);
    }
    EXPECT_EQ(slices.size(), want_slices + late) << "answer " << i;
    for (const RetimedCurve& curve : result.curves) {
      EXPECT_EQ(curve.values.capacity(), 0u);
      EXPECT_EQ(curve.steps.capacity(), 0u);
      EXPECT_TRUE(curve.hold_histogram.empty());
    }
    EXPECT_EQ(result.key_frames, before.key_frames);
    EXPECT_EQ(result.timings.size(), before.timings.size());
  }
}

// A valid request: keyframe and dense curves, sometimes explicit key frames, n, tame, tsume,
// curve overrides and segment overrides with some fields unset.
v1::RetimeCurvesRequest RandomRequest(SplitMix64& rng) {
  v1::RetimeCurvesRequest request;
  v1::CurveSet* set = request.mutable_curves();
  const bool large = rng.OneIn(10);
  const int frames = large ? rng.Int(2000, 6000) : rng.Int(2, 400);
  const int curves = large ? rng.Int(1, 4) : rng.Int(1, 12);
  set->set_fps(rng.OneIn(2) ? 30.0 : 24.0);
  set->set_frame_count(frames);
  set->set_beziers_restricted(true);
  for (int c = 0; c < curves; ++c) {
    v1::Curve* curve = set->add_curves();
    curve->set_id(rng.OneIn(5)
                      ? std::string(static_cast<size_t>(rng.Int(127, 200)), 'a') + std::to_string(c)
                      : "P" + std::to_string(c));
    if (rng.OneIn(4)) {
      for (int f = 0; f < frames; ++f) curve->add_samples(rng.OneIn(5) ? 0.0 : rng.Unit() - 0.5);
    } else {
      ::koma::testing::AddRandomKeyframes(rng, frames, 1, 20, 4, curve);
    }
  }
  // 0: the default key poses (at least frames 0 and frames - 1).
  const int key_poses = ::koma::testing::AddRandomCurvesOptions(rng, 15, &request);
  // At 30 fps, half the time on the default 24 fps film grid, where key poses may merge as
  // they snap: then only segment 0 (always there) is overridden. Otherwise counted in source
  // frames (timing_fps 0).
  const bool grid = set->fps() == 30.0 && frames >= 3 && rng.OneIn(2);
  if (!grid) request.set_timing_fps(0.0);
  const int segments = grid ? 1 : (key_poses > 1 ? key_poses - 1 : 1);
  for (int s = 0; s < segments; ++s) {
    if (!rng.OneIn(3)) continue;
    v1::SegmentOverride* o = request.add_segment_overrides();
    o->set_segment(s);
    if (rng.OneIn(2)) o->set_frames_per_drawing(rng.Int(1, 4));
    if (rng.OneIn(2)) o->set_tame(1.0 + rng.Unit());
    if (rng.OneIn(2)) o->set_tsume(1.0 + rng.Unit());
  }
  return request;
}

TEST(CurvesResponseTest, RandomRequestsAnswerTheMessagesBytes) {
  SplitMix64 rng(7);
  RequestLimits limits;
  int distinct_timings = 0;
  for (int i = 0; i < 200; ++i) {
    const v1::RetimeCurvesRequest request = RandomRequest(rng);
    CurvesAnswer answer;
    const absl::Status status = RetimeCurvesAnswer(request, limits, &answer);
    ASSERT_TRUE(status.ok()) << "request " << i << ": " << status;
    if (answer.result.timings.size() > 1) ++distinct_timings;
    const std::string encoded = Encoded(answer.set, answer.result);
    ASSERT_EQ(encoded, Serialised(answer.set, answer.result)) << "request " << i;
    // And as HandleRetimeCurves (the typed benchmark servers' path) answers it.
    v1::RetimeCurvesResponse response;
    ASSERT_TRUE(HandleRetimeCurves(request, limits, &response).ok());
    ASSERT_EQ(encoded, response.SerializeAsString()) << "request " << i;
  }
  EXPECT_GT(distinct_timings, 10);  // the per-curve n overrides did make several timings
}

}  // namespace
}  // namespace koma::server
