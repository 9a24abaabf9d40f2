#include "client/curves_summary.h"

#include <algorithm>
#include <map>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "client/files.h"
#include "convert/curves_convert.h"
#include "core/key_check.h"

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

// ", 5 merged from 23 keyframe times" when some key pose stands for several keyframe times.
std::string MergedText(const google::protobuf::RepeatedField<int32_t>& merged) {
  int poses = 0, times = 0;
  for (int count : merged) {
    times += count;
    if (count > 1) ++poses;
  }
  if (poses == 0) return "";
  return absl::StrFormat(", %d merged from %d keyframe times", poses, times);
}

// The timing group of each timing index (its name), when the answer has groups.
std::map<int, std::string> GroupOfTiming(const v1::RetimeCurvesResponse& response) {
  std::map<int, std::string> names;
  for (const v1::CurveTimingGroupResult& g : response.timing_groups()) {
    for (int c : g.curves()) {
      if (c >= 0 && c < response.curves_size()) names[response.curves(c).timing()] = g.name();
    }
  }
  return names;
}

// The keys the answer draws: how many it lists, and those that shared a drawing with a key of
// a larger swing (not drawn), as "ID@FRAME".
struct KeyCounts {
  int listed = 0;
  int displaced = 0;  // drawn a drawing early or late
  std::vector<std::string> shared;
};

KeyCounts CountKeys(const v1::RetimeCurvesResponse& response) {
  KeyCounts counts;
  for (const v1::RetimedCurve& curve : response.curves()) {
    for (const v1::KeyDrawing& key : curve.keys()) {
      ++counts.listed;
      if (key.displaced()) ++counts.displaced;
      if (!key.drawn()) counts.shared.push_back(absl::StrCat(curve.id(), "@", key.frame()));
    }
  }
  return counts;
}

// The key check of the answer (core/key_check.h): every stepped curve but those kept as they
// came (timing -1) and the mouth and eyes LipBlink draws (no holds).
KeyCheck CheckAnswerKeys(const CurveSet& curves, const v1::RetimeCurvesResponse& response) {
  std::vector<std::vector<CurvePoint>> steps(static_cast<size_t>(response.curves_size()));
  std::vector<const std::vector<CurvePoint>*> stepped(steps.size(), nullptr);
  for (int c = 0; c < response.curves_size(); ++c) {
    const v1::RetimedCurve& curve = response.curves(c);
    if (curve.timing() < 0 || curve.hold_histogram_size() == 0) continue;
    steps[c] = convert::StepsFromProto(curve.stepped());
    stepped[c] = &steps[c];
  }
  KeyCheckOptions options;
  options.timing_fps = response.timing_fps();
  return CheckKeys(curves, stepped, options);
}

std::string KeyCheckText(const KeyCheck& check) {
  std::string text = absl::StrFormat(
      "  key check    %d keyed extremes, %d missed by more than 0.5%% of their curve's range",
      check.extremes, check.extremes_missed);
  const CurveKeyCheck* worst = nullptr;
  for (const CurveKeyCheck& c : check.curves) {
    if (c.extremes_missed > 0 && (worst == nullptr || c.worst_miss > worst->worst_miss)) worst = &c;
  }
  if (worst != nullptr) {
    absl::StrAppendFormat(&text, " (worst %s at frame %g, %.1f%%)", worst->id,
                          worst->worst_miss_frame, 100.0 * worst->worst_miss);
  }
  absl::StrAppendFormat(&text,
                        "; %d ends missed; drawings a second over %zu moving curves: median "
                        "%.2f, p95 %.2f, max %.2f\n",
                        check.ends_missed, check.curves.size(), check.drawings_per_second_median,
                        check.drawings_per_second_p95, check.drawings_per_second_max);
  return text;
}

}  // namespace

std::string CurvesSummaryText(const CurvesArgs& args, const CurveSet& curves,
                              const v1::RetimeCurvesRequest& request,
                              const v1::RetimeCurvesResponse& response) {
  std::string text =
      absl::StrFormat("%s: %zu curves, %d frames at %.4g fps -> %s\n", InputName(args.input),
                      curves.curves.size(), curves.frame_count, curves.fps,
                      args.timing_only ? std::string("(timing only)") : OutputName(args.output));
  absl::StrAppendFormat(&text, "  key poses (%d%s): %s\n", response.key_frames_size(),
                        MergedText(response.key_frames_merged()),
                        absl::StrJoin(response.key_frames(), ", "));
  if (response.timing_groups_size() > 0) {
    std::vector<std::string> groups;
    const std::map<std::string, v1::CurveTimingGroupMode> modes = convert::TimingGroupModes(request);
    for (const v1::CurveTimingGroupResult& g : response.timing_groups()) {
      const auto mode = modes.find(g.name());
      if (mode != modes.end() && mode->second == v1::GROUP_KEEP) {
        groups.push_back(absl::StrFormat("%s (%d curves, kept as they are)", g.name(),
                                         g.curves_size()));
        continue;
      }
      const bool lip_blink = mode != modes.end() && mode->second == v1::GROUP_LIP_BLINK;
      groups.push_back(absl::StrFormat("%s (%d curves, %s%s, %d key poses%s)", g.name(),
                                       g.curves_size(), lip_blink ? "lipblink, the rest " : "",
                                       OnName(g.frames_per_drawing()), g.key_frames_size(),
                                       MergedText(g.key_frames_merged())));
    }
    absl::StrAppend(&text, "  timing groups: ", absl::StrJoin(groups, "; "), "\n");
  }
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
  const std::map<int, std::string> group_of_timing = GroupOfTiming(response);
  for (const auto& [index, members] : curves_by_timing) {
    if (index < 0 || index >= response.timings_size()) continue;
    const v1::DrawingTiming& timing = response.timings(index);
    // A stepped curve always has holds; the mouth and eyes LipBlink draws have none.
    std::vector<std::string> ids, drawn;
    const v1::RetimedCurve* shown = nullptr;
    for (const v1::RetimedCurve* curve : members) {
      if (curve->hold_histogram_size() == 0) {
        drawn.push_back(curve->id());
        continue;
      }
      ids.push_back(curve->id());
      if (shown == nullptr) shown = curve;
    }
    const auto group = group_of_timing.find(index);
    const std::string name = group == group_of_timing.end() ? "" : group->second + " ";
    if (shown != nullptr) {
      absl::StrAppendFormat(&text, "  %s%s: %d drawings (holds %s) for %s\n", name,
                            OnName(timing.frames_per_drawing()), timing.drawing_start_size(),
                            Histogram(*shown), absl::StrJoin(ids, ", "));
    }
    if (!drawn.empty()) {
      absl::StrAppendFormat(&text,
                            "  %sLipBlink (mouth flaps, anime blinks; %s between them): %s\n",
                            name, OnName(timing.frames_per_drawing()), absl::StrJoin(drawn, ", "));
    }
  }
  const KeyCounts keys = CountKeys(response);
  if (keys.listed > 0) {
    absl::StrAppendFormat(&text, "  keys drawn   %d of %d (first, last and keyed extremes)",
                          keys.listed - static_cast<int>(keys.shared.size()), keys.listed);
    if (keys.displaced > 0) {
      absl::StrAppendFormat(&text, "; %d a drawing early or late (two keys in one hold)",
                            keys.displaced);
    }
    if (!keys.shared.empty()) {
      const size_t shown = std::min<size_t>(keys.shared.size(), 5);
      absl::StrAppendFormat(
          &text, "; %zu shared a drawing with a larger swing: %s%s", keys.shared.size(),
          absl::StrJoin(keys.shared.begin(), keys.shared.begin() + shown, ", "),
          shown < keys.shared.size() ? ", ..." : "");
    }
    absl::StrAppend(&text, "\n");
  }
  if (args.check_keys) absl::StrAppend(&text, KeyCheckText(CheckAnswerKeys(curves, response)));
  if (!args.timing.empty()) {
    absl::StrAppend(&text, "  drawing sheet: ", OutputName(args.timing), "\n");
  }
  return text;
}

nlohmann::json CurvesSummaryJson(const CurvesArgs& args, const CurveSet& curves,
                                 const v1::RetimeCurvesRequest& request,
                                 const v1::RetimeCurvesResponse& response) {
  const std::map<std::string, v1::CurveTimingGroupMode> modes = convert::TimingGroupModes(request);
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
  j["key_frames_merged"] = std::vector<int>(response.key_frames_merged().begin(),
                                            response.key_frames_merged().end());
  j["timing_groups"] = nlohmann::json::array();
  for (const v1::CurveTimingGroupResult& g : response.timing_groups()) {
    std::vector<std::string> ids;
    for (int c : g.curves()) {
      if (c >= 0 && c < response.curves_size()) ids.push_back(response.curves(c).id());
    }
    j["timing_groups"].push_back(
        {{"name", g.name()},
         {"mode", modes.count(g.name()) ? convert::TimingGroupModeName(modes.at(g.name()))
                                        : "step"},
         {"curves", ids},
         {"frames_per_drawing", g.frames_per_drawing()},
         {"timing", g.timing()},
         {"key_frames", std::vector<int>(g.key_frames().begin(), g.key_frames().end())},
         {"key_frames_merged",
          std::vector<int>(g.key_frames_merged().begin(), g.key_frames_merged().end())}});
  }
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
    int shared = 0, displaced = 0;
    for (const v1::KeyDrawing& key : curve.keys()) {
      shared += key.drawn() ? 0 : 1;
      displaced += key.displaced() ? 1 : 0;
    }
    j["curves"].push_back({{"id", curve.id()},
                           {"timing", curve.timing()},
                           {"hold_histogram", histogram},
                           {"keys_drawn", curve.keys_size() - shared},
                           {"keys_displaced", displaced},
                           {"keys_shared", shared}});
  }
  const KeyCounts keys = CountKeys(response);
  j["keys_drawn"] = keys.listed - static_cast<int>(keys.shared.size());
  j["keys_displaced"] = keys.displaced;
  j["keys_shared"] = keys.shared.size();
  if (args.check_keys) {
    const KeyCheck check = CheckAnswerKeys(curves, response);
    nlohmann::json missed = nlohmann::json::array();
    for (const CurveKeyCheck& c : check.curves) {
      if (c.extremes_missed == 0 && !c.first_missed && !c.last_missed) continue;
      missed.push_back({{"id", c.id},
                        {"extremes", c.extremes},
                        {"extremes_missed", c.extremes_missed},
                        {"worst_miss", c.worst_miss},
                        {"worst_miss_frame", c.worst_miss_frame},
                        {"first_missed", c.first_missed},
                        {"last_missed", c.last_missed}});
    }
    j["key_check"] = {{"curves", check.curves.size()},
                      {"extremes", check.extremes},
                      {"extremes_missed", check.extremes_missed},
                      {"ends_missed", check.ends_missed},
                      {"drawings_per_second",
                       {{"median", check.drawings_per_second_median},
                        {"p95", check.drawings_per_second_p95},
                        {"max", check.drawings_per_second_max}}},
                      {"missed", missed}};
  }
  return j;
}

}  // namespace koma::client
