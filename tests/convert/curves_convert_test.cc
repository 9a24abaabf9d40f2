// convert/curves_convert.h: core curves -> koma.v1 -> core gives the same curves back, and a
// malformed curve gets INVALID_ARGUMENT naming its field (the server's messages: they are
// what a client reads back).
#include "convert/curves_convert.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/testing/status_matchers.h"

namespace koma::convert {
namespace {

using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

void ExpectSamePoint(const CurvePoint& a, const CurvePoint& b) {
  EXPECT_EQ(a.frame, b.frame);
  EXPECT_EQ(a.value, b.value);
}

// One curve of each segment type and a dense one; non-Bezier handles stay zero (the wire
// carries handles for Beziers only).
CurveSet EverySegmentType() {
  CurveSet set;
  set.fps = 24;
  set.frame_count = 31;
  set.beziers_restricted = true;
  Curve keys;
  keys.id = "ParamAngleX";
  keys.start = {0, -1.5};
  keys.segments.push_back({SegmentType::kLinear, {}, {4, 2}});
  keys.segments.push_back({SegmentType::kBezier, {{6, 3}, {8, 0.25}}, {10, 1}});
  keys.segments.push_back({SegmentType::kStepped, {}, {20, -3}});
  keys.segments.push_back({SegmentType::kInverseStepped, {}, {30, 7}});
  set.curves.push_back(keys);
  Curve dense;
  dense.id = "ParamMouthOpenY";
  for (int f = 0; f < set.frame_count; ++f) dense.samples.push_back(0.03125 * f);
  set.curves.push_back(dense);
  return set;
}

TEST(CurvesConvertTest, CoreToProtoAndBackIsTheSameSet) {
  const CurveSet in = EverySegmentType();
  ASSERT_OK_AND_ASSIGN(const CurveSet out, CurveSetFromProto(CurveSetToProto(in), "curves"));
  EXPECT_EQ(out.fps, in.fps);
  EXPECT_EQ(out.frame_count, in.frame_count);
  EXPECT_EQ(out.beziers_restricted, in.beziers_restricted);
  ASSERT_EQ(out.curves.size(), in.curves.size());
  for (size_t c = 0; c < in.curves.size(); ++c) {
    EXPECT_EQ(out.curves[c].id, in.curves[c].id);
    EXPECT_EQ(out.curves[c].samples, in.curves[c].samples);
    ExpectSamePoint(out.curves[c].start, in.curves[c].start);
    ASSERT_EQ(out.curves[c].segments.size(), in.curves[c].segments.size());
    for (size_t s = 0; s < in.curves[c].segments.size(); ++s) {
      const CurveSegment& a = out.curves[c].segments[s];
      const CurveSegment& b = in.curves[c].segments[s];
      EXPECT_EQ(a.type, b.type) << "segment " << s;
      ExpectSamePoint(a.handles[0], b.handles[0]);
      ExpectSamePoint(a.handles[1], b.handles[1]);
      ExpectSamePoint(a.end, b.end);
    }
  }
}

TEST(CurvesConvertTest, OneCurveConvertsAsInTheSet) {
  const v1::CurveSet proto = CurveSetToProto(EverySegmentType());
  ASSERT_OK_AND_ASSIGN(const Curve curve, CurveFromProto(proto.curves(0), "curves.curves[0]"));
  ASSERT_EQ(curve.segments.size(), 4u);
  EXPECT_EQ(curve.segments[1].type, SegmentType::kBezier);
  ExpectSamePoint(curve.segments[1].handles[1], {8, 0.25});
}

TEST(CurvesConvertTest, UnknownSegmentTypeNamesTheSegment) {
  v1::CurveSet proto = CurveSetToProto(EverySegmentType());
  proto.mutable_curves(0)->mutable_segments(2)->set_type(static_cast<v1::SegmentType>(9));
  EXPECT_THAT(CurveSetFromProto(proto, "curves").status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       "curves.curves[0].segments[2].type: 9 is not a segment type (1 LINEAR, "
                       "2 BEZIER, 3 STEPPED, 4 INVERSE_STEPPED)"));
  proto.mutable_curves(0)->mutable_segments(2)->set_type(v1::SEGMENT_TYPE_UNSPECIFIED);
  EXPECT_THAT(CurveFromProto(proto.curves(0), "x").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("x.segments[2].type: 0 ")));
}

TEST(CurvesConvertTest, BothFormsOrNeitherIsRefused) {
  v1::CurveSet proto = CurveSetToProto(EverySegmentType());
  proto.mutable_curves(1)->mutable_start()->set_frame(0);
  EXPECT_THAT(CurveSetFromProto(proto, "curves").status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       "curves.curves[1]: both keyframes (start/segments) and samples are set; "
                       "give one form"));
  proto.mutable_curves(1)->Clear();
  proto.mutable_curves(1)->set_id("empty");
  EXPECT_THAT(CurveSetFromProto(proto, "curves").status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       "curves.curves[1]: empty curve (neither start nor samples is set)"));
}

TEST(CurvesConvertTest, CoreValidationIsPrefixedWithThePath) {
  CurveSet set = EverySegmentType();
  set.frame_count = 1;
  EXPECT_THAT(CurveSetFromProto(CurveSetToProto(set), "curves").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("curves.frame_count")));
}

TEST(CurvesConvertTest, SteppedKeyframesRoundTrip) {
  const std::vector<CurvePoint> steps{{0, 1}, {3, 2.5}, {9, -4}};
  v1::Curve proto;
  SteppedKeyframesToProto(steps, &proto);
  ASSERT_EQ(proto.segments_size(), 2);
  EXPECT_EQ(proto.segments(1).type(), v1::SEGMENT_STEPPED);
  const std::vector<CurvePoint> back = StepsFromProto(proto);
  ASSERT_EQ(back.size(), steps.size());
  for (size_t k = 0; k < steps.size(); ++k) ExpectSamePoint(back[k], steps[k]);
  v1::Curve none;
  SteppedKeyframesToProto({}, &none);
  EXPECT_FALSE(none.has_start());
  EXPECT_EQ(none.segments_size(), 0);
}

TEST(CurvesConvertTest, ResponseCurveAsReplacement) {
  v1::RetimedCurve retimed;
  for (double v : {1.0, 1.0, 4.0}) retimed.add_values(v);
  SteppedKeyframesToProto({{0, 1}, {2, 4}}, retimed.mutable_stepped());
  v1::ConvertedCurve converted;
  *converted.mutable_values() = retimed.values();
  *converted.mutable_stepped() = retimed.stepped();
  for (const CurveReplacement& r :
       {ReplacementFromProto(retimed), ReplacementFromProto(converted)}) {
    EXPECT_EQ(r.values, (std::vector<double>{1, 1, 4}));
    ASSERT_EQ(r.steps.size(), 2u);
    ExpectSamePoint(r.steps[1], {2, 4});
  }
}

}  // namespace
}  // namespace koma::convert
