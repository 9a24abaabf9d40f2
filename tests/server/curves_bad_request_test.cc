// Every malformed RetimeCurves request gets INVALID_ARGUMENT (or RESOURCE_EXHAUSTED) with the
// field path and value, through an in-process channel to the real service.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"
#include "tests/server/bad_request_table.h"
#include "tests/server/curves_request_builder.h"
#include "tests/server/in_process_server.h"

namespace koma::server {
namespace {

using ::koma::testing::InProcessServer;
using BadCurves = ::koma::testing::BadRequest<v1::RetimeCurvesRequest>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

v1::Curve& CurveOf(v1::RetimeCurvesRequest& r, int i) {
  return *r.mutable_curves()->mutable_curves(i);
}
v1::CurveSegment& SegmentOf(v1::RetimeCurvesRequest& r, int i) {
  return *CurveOf(r, 0).mutable_segments(i);
}

std::vector<BadCurves> BadRequests() {
  using C = grpc::StatusCode;
  const C kInvalid = C::INVALID_ARGUMENT;
  return {
      {"NoCurveSet", [](auto& r) { r.clear_curves(); }, kInvalid, "curves: required"},
      {"FpsZero", [](auto& r) { r.mutable_curves()->set_fps(0.0); }, kInvalid,
       "curves.fps: 0"},
      {"FpsNaN", [](auto& r) { r.mutable_curves()->set_fps(kNaN); }, kInvalid,
       "curves.fps: nan"},
      {"OneFrame", [](auto& r) { r.mutable_curves()->set_frame_count(1); }, kInvalid,
       "curves.frame_count: 1"},
      {"NoCurves", [](auto& r) { r.mutable_curves()->clear_curves(); }, kInvalid,
       "curves.curves"},
      {"EmptyId", [](auto& r) { CurveOf(r, 1).set_id(""); }, kInvalid, "curves.curves[1].id"},
      {"DuplicateId", [](auto& r) { CurveOf(r, 1).set_id("ParamAngleX"); }, kInvalid,
       "curves.curves[1].id: \"ParamAngleX\""},
      {"EmptyCurve", [](auto& r) { CurveOf(r, 0).Clear(); CurveOf(r, 0).set_id("A"); },
       kInvalid, "curves.curves[0]: empty curve"},
      {"BothForms", [](auto& r) { CurveOf(r, 0).add_samples(1.0); }, kInvalid,
       "curves.curves[0]: both keyframes"},
      {"UnknownSegmentType",
       [](auto& r) { SegmentOf(r, 1).set_type(static_cast<v1::SegmentType>(9)); }, kInvalid,
       "curves.curves[0].segments[1].type: 9 is not a segment type"},
      {"UnspecifiedSegmentType",
       [](auto& r) { SegmentOf(r, 0).set_type(v1::SEGMENT_TYPE_UNSPECIFIED); }, kInvalid,
       "curves.curves[0].segments[0].type: 0"},
      {"SegmentTimesDecrease",
       [](auto& r) { SegmentOf(r, 1).mutable_end()->set_frame(5.0); }, kInvalid,
       "curves.curves[0].segments[1].end.frame: 5"},
      {"SegmentEndsWhereItStarts",
       [](auto& r) { SegmentOf(r, 0).mutable_end()->set_frame(0.0); }, kInvalid,
       "curves.curves[0].segments[0].end.frame: 0"},
      {"HandlesOutOfOrderRestricted",
       [](auto& r) {
         SegmentOf(r, 1).mutable_handle1()->set_frame(25.0);
         SegmentOf(r, 1).mutable_handle2()->set_frame(15.0);
       },
       kInvalid, "curves.curves[0].segments[1]"},
      {"HandleOutsideSegment",
       [](auto& r) { SegmentOf(r, 1).mutable_handle1()->set_frame(40.0); }, kInvalid,
       "curves.curves[0].segments[1].handle"},
      {"ValueNaN", [](auto& r) { SegmentOf(r, 0).mutable_end()->set_value(kNaN); }, kInvalid,
       "curves.curves[0].segments[0].end.value: nan"},
      {"SampleInf", [](auto& r) { CurveOf(r, 1).set_samples(4, kInf); }, kInvalid,
       "curves.curves[1].samples[4]: inf"},
      {"TooFewSamples", [](auto& r) { CurveOf(r, 1).mutable_samples()->RemoveLast(); },
       kInvalid, "curves.curves[1].samples"},
      {"KeysUnsorted",
       [](auto& r) { for (int k : {0, 20, 10, 30}) r.add_key_frames(k); }, kInvalid,
       "key_frames"},
      {"KeysDuplicate",
       [](auto& r) { for (int k : {0, 10, 10, 30}) r.add_key_frames(k); }, kInvalid,
       "key_frames"},
      {"KeyOutsideRange", [](auto& r) { for (int k : {0, 10, 31}) r.add_key_frames(k); },
       kInvalid, "key_frames[2]: 31"},
      {"NegativeKey", [](auto& r) { r.add_key_frames(-1); }, kInvalid, "key_frames[0]: -1"},
      {"FramesPerDrawingZero", [](auto& r) { r.set_frames_per_drawing(0); }, kInvalid,
       "frames_per_drawing: 0"},
      {"TameBelowOne", [](auto& r) { r.set_tame(0.5); }, kInvalid, "tame: 0.5"},
      {"TsumeNaN", [](auto& r) { r.set_tsume(kNaN); }, kInvalid, "tsume: nan"},
      {"TsumeInf", [](auto& r) { r.set_tsume(kInf); }, kInvalid, "tsume: inf"},
      {"OverrideUnknownCurve",
       [](auto& r) {
         auto* o = r.add_curve_overrides();
         o->set_curve_id("ParamHair");
         o->set_frames_per_drawing(2);
       },
       kInvalid, "curve_overrides[0].curve_id: \"ParamHair\" is not a curve"},
      {"OverrideZero",
       [](auto& r) {
         auto* o = r.add_curve_overrides();
         o->set_curve_id("ParamArm");
         o->set_frames_per_drawing(0);
       },
       kInvalid, "curve_overrides[0].frames_per_drawing: 0"},
      {"OverrideTwice",
       [](auto& r) {
         for (int i = 0; i < 2; ++i) {
           auto* o = r.add_curve_overrides();
           o->set_curve_id("ParamArm");
           o->set_frames_per_drawing(2);
         }
       },
       kInvalid, "curve_overrides[1].curve_id: \"ParamArm\" is given twice"},
      {"SegmentOverrideOutOfRange",
       [](auto& r) { r.add_segment_overrides()->set_segment(7); }, kInvalid,
       "segment_overrides[0].segment: 7"},
      {"SegmentOverrideTameBelowOne",
       [](auto& r) {
         auto* o = r.add_segment_overrides();
         o->set_segment(0);
         o->set_tame(0.9);
       },
       kInvalid, "segment_overrides[0].tame: 0.9"},
      {"GroupWithoutName", [](auto& r) { r.add_timing_groups()->add_ids("ParamArm"); },
       kInvalid, "timing_groups[0].name: required"},
      {"GroupNamedBody",
       [](auto& r) {
         auto* g = r.add_timing_groups();
         g->set_name("body");
         g->add_ids("ParamArm");
       },
       kInvalid, "timing_groups[0].name: \"body\" is the default group's"},
      {"GroupNamedTwice",
       [](auto& r) {
         for (const char* id : {"ParamArm", "ParamAngle*"}) {
           auto* g = r.add_timing_groups();
           g->set_name("arms");
           g->add_ids(id);
         }
       },
       kInvalid, "timing_groups[1].name: \"arms\" is already timing_groups[0]'s"},
      {"GroupWithoutIds", [](auto& r) { r.add_timing_groups()->set_name("hair"); }, kInvalid,
       "timing_groups[0].ids: empty"},
      {"GroupOnZero",
       [](auto& r) {
         auto* g = r.add_timing_groups();
         g->set_name("hair");
         g->add_ids("ParamHair*");
         g->set_frames_per_drawing(0);
       },
       kInvalid, "timing_groups[0].frames_per_drawing: 0 must be >= 1"},
      {"GroupTsumeNaN",
       [](auto& r) {
         auto* g = r.add_timing_groups();
         g->set_name("hair");
         g->add_ids("ParamHair*");
         g->set_tsume(kNaN);
       },
       kInvalid, "timing_groups[0].tsume: nan"},
      {"GroupKeyOutsideRange",
       [](auto& r) {
         auto* g = r.add_timing_groups();
         g->set_name("arm");
         g->add_ids("ParamArm");
         g->add_key_frames(31);
       },
       kInvalid, "timing_groups[0].key_frames[0]: 31 is outside [0, 30]"},
      {"GroupPatternsOverWorkLimit",
       [](auto& r) {
         auto* g = r.add_timing_groups();
         g->set_name("many");
         for (int i = 0; i < 30'000; ++i) g->add_ids("Param?");
       },
       C::RESOURCE_EXHAUSTED,
       "timing_groups: 210000 bytes of id patterns x 2 curves = 420000 exceeds the server limit "
       "--max_values=50000"},
      {"GroupsOverWorkLimit",
       [](auto& r) {
         for (int i = 0; i < 2000; ++i) {
           auto* g = r.add_timing_groups();
           g->set_name("g" + std::to_string(i));
           g->add_ids("X");
         }
       },
       C::RESOURCE_EXHAUSTED,
       "timing_groups: 2000 groups + the default x 31 frames = 62031 exceeds the server limit "
       "--max_values=50000"},
      {"KeysTooLargeToInterpolate",
       [](auto& r) {
         CurveOf(r, 0).mutable_start()->set_value(-1.5e308);
         SegmentOf(r, 0).mutable_end()->set_value(1.5e308);
       },
       C::OUT_OF_RANGE, "curves.curves[0]: evaluates to"},
      {"OverValueLimit",
       [](auto& r) {
         r.mutable_curves()->set_frame_count(40'000);
         CurveOf(r, 1).mutable_samples()->Resize(40'000, 0.0);
       },
       C::RESOURCE_EXHAUSTED, "exceeds the server limit --max_values=50000"},
  };
}

class CurvesBadRequestTest
    : public koma::testing::BadRequestSuite<CurvesBadRequestTest, v1::RetimeCurvesRequest> {
 public:
  static server::ServerConfig SuiteConfig() { return InProcessServer::Config(1, 50'000); }
  static v1::RetimeCurvesRequest ValidRequest() { return koma::testing::MakeCurvesRequest(); }
};

KOMA_BAD_REQUEST_TABLE(CurvesBadRequestTest, CurvesBadRequestTableTest, BadRequests)

}  // namespace
}  // namespace koma::server
