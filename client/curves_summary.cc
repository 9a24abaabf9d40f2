#include "client/curves_summary.h"

#include <map>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "client/files.h"

namespace koma::client {
namespace {

// "on ones", "on twos", "on threes", then "on 4s".
std::string OnName(int n) {
  switch (n) {
    case 1:
      return "on ones";
    case 2:
      return "on twos";
    case 3:
      return "on threes";
    default:
      return absl::StrCat("on ", n, "s");
  }
}

std::string Histogram(const v1::RetimedCurve& curve) {
  std::vector<std::string> parts;
  for (const v1::HoldCount& c : curve.hold_histogram()) {
    parts.push_back(absl::StrCat(c.drawings(), " x ", c.length(), "f"));
  }
  return absl::StrJoin(parts, ", ");
}

}  // namespace

std::string CurvesSummaryText(const CurvesArgs& args, const CurveSet& curves,
                              const v1::RetimeCurvesResponse& response) {
  std::string text =
      absl::StrFormat("%s: %zu curves, %d frames at %.4g fps -> %s\n", InputName(args.input),
                      curves.curves.size(), curves.frame_count, curves.fps,
                      args.timing_only ? std::string("(timing only)") : OutputName(args.output));
  absl::StrAppendFormat(&text, "  key poses (%d): %s\n", response.key_frames_size(),
                        absl::StrJoin(response.key_frames(), ", "));
  if (response.timing_fps() > 0) {
    absl::StrAppendFormat(
        &text,
        "  on the %.4g fps film grid (holds in its frames, %.1f ms each); key poses at grid "
        "frames %s\n",
        response.timing_fps(), 1000.0 / response.timing_fps(),
        absl::StrJoin(response.key_grid_frames(), ", "));
  }
  std::map<int, std::vector<const v1::RetimedCurve*>> curves_by_timing;
  for (const v1::RetimedCurve& curve : response.curves()) {
    curves_by_timing[curve.timing()].push_back(&curve);
  }
  for (const auto& [index, members] : curves_by_timing) {
    if (index < 0 || index >= response.timings_size()) continue;
    const v1::DrawingTiming& timing = response.timings(index);
    std::vector<std::string> ids;
    for (const v1::RetimedCurve* curve : members) ids.push_back(curve->id());
    absl::StrAppendFormat(&text, "  %s: %d drawings (holds %s) for %s\n",
                          OnName(timing.frames_per_drawing()), timing.drawing_start_size(),
                          Histogram(*members.front()), absl::StrJoin(ids, ", "));
  }
  if (!args.timing.empty()) {
    absl::StrAppend(&text, "  drawing sheet: ", OutputName(args.timing), "\n");
  }
  return text;
}

nlohmann::json CurvesSummaryJson(const CurvesArgs& args, const CurveSet& curves,
                                 const v1::RetimeCurvesResponse& response) {
  nlohmann::json j;
  j["input"] = args.input;
  j["outputs"] = nlohmann::json::object();
  if (!args.timing_only && !args.output.empty()) j["outputs"]["curves"] = args.output;
  if (!args.timing.empty()) j["outputs"]["timing"] = args.timing;
  if (!args.report.empty()) j["outputs"]["report"] = args.report;
  if (!args.xdts.empty()) j["outputs"]["xdts"] = args.xdts;
  j["curve_count"] = curves.curves.size();
  j["frames"] = curves.frame_count;
  j["fps"] = curves.fps;
  j["timing_fps"] = response.timing_fps();
  j["key_frames"] = std::vector<int>(response.key_frames().begin(), response.key_frames().end());
  j["key_grid_frames"] =
      std::vector<int>(response.key_grid_frames().begin(), response.key_grid_frames().end());
  j["timings"] = nlohmann::json::array();
  for (const v1::DrawingTiming& timing : response.timings()) {
    j["timings"].push_back({{"frames_per_drawing", timing.frames_per_drawing()},
                            {"drawings", timing.drawing_start_size()}});
  }
  j["curves"] = nlohmann::json::array();
  for (const v1::RetimedCurve& curve : response.curves()) {
    nlohmann::json histogram = nlohmann::json::array();
    for (const v1::HoldCount& c : curve.hold_histogram()) {
      histogram.push_back({{"length", c.length()}, {"drawings", c.drawings()}});
    }
    j["curves"].push_back(
        {{"id", curve.id()}, {"timing", curve.timing()}, {"hold_histogram", histogram}});
  }
  return j;
}

}  // namespace koma::client
