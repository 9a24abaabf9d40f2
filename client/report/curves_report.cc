#include "client/report/curves_report.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "client/report/input_curves.h"
#include "client/report/report_data.h"
#include "client/xdts_sheets.h"
#include "convert/curves_convert.h"
#include "core/film_grid.h"

namespace koma::client::report {
namespace {

// A retimed curve's stepped keys as a plot: each point's time in seconds and its value. A
// curve with more keys than a plot shows gives its per-frame values, thinned, instead.
nlohmann::json AfterPlot(const v1::RetimedCurve& curve, double fps) {
  // A kept curve (timing -1) has no steps: its values are the input's.
  if (curve.timing() < 0 || curve.stepped().segments_size() + 1 > kMaxPlotPoints) {
    nlohmann::json plot =
        ThinnedPlot(absl::MakeConstSpan(curve.values().data(), curve.values_size()), 1.0 / fps);
    plot["stepped"] = false;
    return plot;
  }
  nlohmann::json x = nlohmann::json::array();
  nlohmann::json y = nlohmann::json::array();
  x.push_back(Round6(curve.stepped().start().frame() / fps));
  y.push_back(Round6(curve.stepped().start().value()));
  for (const v1::CurveSegment& s : curve.stepped().segments()) {
    x.push_back(Round6(s.end().frame() / fps));
    y.push_back(Round6(s.end().value()));
  }
  return {{"x", std::move(x)}, {"y", std::move(y)}, {"stepped", true}};
}

}  // namespace

std::string CurvesReportWriter::Title() const { return absl::StrCat("koma curves: ", input_name_); }

nlohmann::json CurvesReportWriter::Data() const {
  const v1::RetimeCurvesRequest& q = request_;
  const v1::RetimeCurvesResponse& r = response_;
  const double fps = q.curves().fps();
  const int frames = q.curves().frame_count();
  const bool grid = r.timing_fps() > 0;
  const std::optional<FilmGrid> film = grid ? FilmGrid::Make(fps, r.timing_fps()) : std::nullopt;

  nlohmann::json options = nlohmann::json::array();
  options.push_back({"frames_per_drawing", q.has_frames_per_drawing()
                                               ? absl::StrCat(q.frames_per_drawing())
                                               : std::string("3 (default)")});
  options.push_back({"key poses", q.key_frames_size() > 0 ? "given"
                                  : q.has_merge_key_poses() && !q.merge_key_poses()
                                      ? "every keyframe time"
                                      : "the keyframe times, merged into poses"});
  std::vector<std::string> group_names;
  for (const v1::CurveTimingGroupResult& g : r.timing_groups()) {
    group_names.push_back(absl::StrCat(g.name(), " (", g.curves_size(), ")"));
  }
  options.push_back({"timing groups", group_names.empty() ? std::string("one")
                                                          : absl::StrJoin(group_names, ", ")});
  options.push_back({"tame", Round6(q.has_tame() ? q.tame() : 1.0)});
  options.push_back({"tsume", Round6(q.has_tsume() ? q.tsume() : 1.0)});
  std::vector<std::string> overrides;
  for (const v1::CurveOverride& o : q.curve_overrides()) {
    overrides.push_back(absl::StrCat(o.curve_id(), "=", o.frames_per_drawing()));
  }
  options.push_back(
      {"curve overrides", overrides.empty() ? "none" : absl::StrJoin(overrides, ", ")});
  options.push_back({"segment overrides", q.segment_overrides_size()});
  options.push_back({"timing_fps", grid ? absl::StrFormat("%.6g (film grid)", r.timing_fps())
                                        : std::string("0 (counted in source frames)")});

  nlohmann::json counts = nlohmann::json::array();
  counts.push_back({"curves", r.curves_size()});
  counts.push_back({"frames", frames});
  counts.push_back({"fps", Round6(fps)});
  if (film) counts.push_back({"grid frames", film->GridFrameCount(frames)});
  counts.push_back({"key poses", r.key_frames_size()});
  int merged_poses = 0;
  for (int m : r.key_frames_merged()) merged_poses += m > 1 ? 1 : 0;
  if (r.key_frames_merged_size() > 0) counts.push_back({"key poses merged", merged_poses});
  for (const v1::DrawingTiming& t : r.timings()) {
    counts.push_back(
        {absl::StrCat("drawings on ", t.frames_per_drawing(), "s"), t.drawing_start_size()});
  }

  nlohmann::json data;
  data["header"] = Header("RetimeCurves", input_name_, options, counts);
  data["fps"] = fps;
  data["frames"] = frames;
  data["timing_fps"] = r.timing_fps();
  data["grid_count"] = film ? film->GridFrameCount(frames) : 0;
  std::vector<int> grid_first_frame;  // per grid frame: the first source frame at or after it
  if (film) {
    const int count = film->GridFrameCount(frames);
    for (int g = 0; g < count; ++g) grid_first_frame.push_back(film->FirstSourceFrameAtOrAfter(g));
  }
  data["grid_first_frame"] = grid_first_frame;
  data["key_frames"] = std::vector<int>(r.key_frames().begin(), r.key_frames().end());
  data["key_grid_frames"] =
      std::vector<int>(r.key_grid_frames().begin(), r.key_grid_frames().end());
  // The timing groups, each with its key poses and how many keyframe times each merges; one
  // group of every curve when the answer lists none.
  nlohmann::json groups = nlohmann::json::array();
  std::vector<int> group_of_curve(static_cast<size_t>(r.curves_size()), 0);
  const std::map<std::string, v1::CurveTimingGroupMode> modes = convert::TimingGroupModes(q);
  if (r.timing_groups_size() == 0) {
    groups.push_back(
        {{"name", "body"},
         {"mode", "step"},
         {"key_frames", data["key_frames"]},
         {"key_grid_frames", data["key_grid_frames"]},
         {"key_merged",
          std::vector<int>(r.key_frames_merged().begin(), r.key_frames_merged().end())}});
  }
  for (int g = 0; g < r.timing_groups_size(); ++g) {
    const v1::CurveTimingGroupResult& group = r.timing_groups(g);
    for (int c : group.curves()) {
      if (c >= 0 && c < r.curves_size()) group_of_curve[static_cast<size_t>(c)] = g;
    }
    const auto mode = modes.find(group.name());
    groups.push_back(
        {{"name", group.name()},
         {"mode", convert::TimingGroupModeName(mode == modes.end() ? v1::GROUP_STEP : mode->second)},
         {"key_frames", std::vector<int>(group.key_frames().begin(), group.key_frames().end())},
         {"key_grid_frames",
          std::vector<int>(group.key_grid_frames().begin(), group.key_grid_frames().end())},
         {"key_merged",
          std::vector<int>(group.key_frames_merged().begin(), group.key_frames_merged().end())},
         {"curves", group.curves_size()}});
  }
  data["groups"] = groups;
  nlohmann::json timings = nlohmann::json::array();
  for (const v1::DrawingTiming& t : r.timings()) {
    timings.push_back(
        {{"n", t.frames_per_drawing()},
         {"drawing_of_frame",
          std::vector<int>(t.drawing_of_frame().begin(), t.drawing_of_frame().end())},
         {"drawing_start", std::vector<int>(t.drawing_start().begin(), t.drawing_start().end())},
         {"drawing_start_grid",
          std::vector<int>(t.drawing_start_grid().begin(), t.drawing_start_grid().end())}});
  }
  data["timings"] = timings;
  nlohmann::json curves = nlohmann::json::array();
  for (int i = 0; i < r.curves_size(); ++i) {
    const v1::RetimedCurve& c = r.curves(i);
    nlohmann::json histogram = nlohmann::json::array();
    for (const v1::HoldCount& h : c.hold_histogram())
      histogram.push_back({h.length(), h.drawings()});
    std::vector<double> before;
    for (int k = 0; k < q.curves().curves_size(); ++k) {
      if (q.curves().curves(k).id() == c.id()) before = SampleInputCurve(q.curves(), k);
    }
    // The keys koma draws exactly: [time s, value, drawn, displaced, the showing drawing's
    // start s] (docs/semantics.md, "Every key is drawn").
    nlohmann::json keys = nlohmann::json::array();
    const v1::DrawingTiming* timing =
        c.timing() >= 0 && c.timing() < r.timings_size() ? &r.timings(c.timing()) : nullptr;
    for (const v1::KeyDrawing& k : c.keys()) {
      double start = k.frame() / fps;
      if (timing != nullptr && k.drawing() >= 0) {
        if (grid && k.drawing() < timing->drawing_start_grid_size()) {
          start = timing->drawing_start_grid(k.drawing()) / r.timing_fps();
        } else if (!grid && k.drawing() < timing->drawing_start_size()) {
          start = timing->drawing_start(k.drawing()) / fps;
        }
      }
      keys.push_back({Round6(k.frame() / fps), Round6(k.value()), k.drawn(), k.displaced(),
                      Round6(start)});
    }
    curves.push_back({{"id", c.id()},
                      {"timing", c.timing()},
                      {"group", group_of_curve[static_cast<size_t>(i)]},
                      {"before", ThinnedPlot(before, 1.0 / fps)},
                      {"after", AfterPlot(c, fps)},
                      {"histogram", histogram},
                      {"keys", keys}});
  }
  data["curves"] = curves;
  data["xdts"] = ExposureSheetData(CurvesXdtsSheet(r, XdtsClipName(input_name_, "")));
  return data;
}

absl::Status WriteCurvesReport(const std::string& path, const v1::RetimeCurvesRequest& request,
                               const v1::RetimeCurvesResponse& response,
                               const std::string& input_name) {
  if (!request.has_curves()) {
    // The file forms (motion3_json, csv_text) are not parsed here: the CLI sends the curves.
    return absl::InvalidArgumentError(
        absl::StrCat("--report ", path, ": the request has no parsed curves to draw"));
  }
  return WriteReport(path, CurvesReportWriter(request, response, input_name));
}

}  // namespace koma::client::report
