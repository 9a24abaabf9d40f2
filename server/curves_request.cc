#include "server/curves_request.h"

#include <algorithm>
#include <map>
#include <string>
#include <utility>

#include "absl/container/flat_hash_set.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"
#include "convert/curves_convert.h"
#include "core/film_grid.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "server/curve_convert.h"

namespace koma::server {
namespace {

// CurveOverride entries -> curve id -> n, each id known and given once, n >= 1.
absl::Status ConvertCurveOverrides(const v1::RetimeCurvesRequest& request, const CurveSet& set,
                                   KomaUchiOptions& options) {
  // Most requests have no overrides: then no set of ids (a copy of every id) is made.
  if (request.curve_overrides_size() == 0) return absl::OkStatus();
  absl::flat_hash_set<absl::string_view> ids;  // views of set.curves' ids, which outlive it
  ids.reserve(set.curves.size());
  for (const Curve& curve : set.curves) ids.insert(curve.id);
  for (int i = 0; i < request.curve_overrides_size(); ++i) {
    const v1::CurveOverride& o = request.curve_overrides(i);
    const std::string path = absl::StrCat("curve_overrides[", i, "]");
    if (ids.count(o.curve_id()) == 0) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, ".curve_id: \"", o.curve_id(), "\" is not a curve of the request"));
    }
    if (o.frames_per_drawing() < 1) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, ".frames_per_drawing: ", o.frames_per_drawing(), " must be >= 1"));
    }
    if (!options.curve_frames_per_drawing.emplace(o.curve_id(), o.frames_per_drawing()).second) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, ".curve_id: \"", o.curve_id(), "\" is given twice"));
    }
  }
  return absl::OkStatus();
}

KomaUchiOptions ConvertOptions(const v1::RetimeCurvesRequest& request) {
  KomaUchiOptions options;
  options.key_frames.assign(request.key_frames().begin(), request.key_frames().end());
  if (request.has_frames_per_drawing()) options.frames_per_drawing = request.frames_per_drawing();
  if (request.has_tame()) options.tame = request.tame();
  if (request.has_tsume()) options.tsume = request.tsume();
  for (const v1::SegmentOverride& in : request.segment_overrides()) {
    SegmentOverride out;
    out.segment = in.segment();
    if (in.has_frames_per_drawing()) out.frames_per_drawing = in.frames_per_drawing();
    if (in.has_tame()) out.tame = in.tame();
    if (in.has_tsume()) out.tsume = in.tsume();
    options.segment_overrides.push_back(out);
  }
  options.timing_fps = request.has_timing_fps() ? request.timing_fps() : kDefaultTimingFps;
  options.merge_key_poses = !request.has_merge_key_poses() || request.merge_key_poses();
  for (const v1::CurveTimingGroup& in : request.timing_groups()) {
    CurveTimingGroup out;
    out.name = in.name();
    out.ids.assign(in.ids().begin(), in.ids().end());
    if (in.has_frames_per_drawing()) out.frames_per_drawing = in.frames_per_drawing();
    if (in.has_tame()) out.tame = in.tame();
    if (in.has_tsume()) out.tsume = in.tsume();
    out.key_frames.assign(in.key_frames().begin(), in.key_frames().end());
    if (in.mode() == v1::GROUP_KEEP) out.mode = TimingGroupMode::kKeep;
    if (in.mode() == v1::GROUP_LIP_BLINK) out.mode = TimingGroupMode::kLipBlink;
    options.groups.push_back(std::move(out));
  }
  if (request.timing_groups_size() == 0 &&
      (!request.has_default_timing_groups() || request.default_timing_groups())) {
    options.groups = DefaultLive2dTimingGroups();
  }
  return options;
}

// Each timing group builds its own timings (a few arrays over every frame) and matches its
// patterns against every id: both count against --max_values as the clip's values do.
absl::Status CheckGroupWork(const CurveSet& set, const KomaUchiOptions& options,
                            const RequestLimits& limits) {
  if (options.groups.empty()) return absl::OkStatus();
  const int64_t groups = static_cast<int64_t>(options.groups.size());
  const int64_t timing_work = (groups + 1) * set.frame_count;
  if (timing_work > limits.max_values) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "timing_groups: ", groups, " groups + the default x ", set.frame_count,
        " frames = ", timing_work, " exceeds the server limit --max_values=", limits.max_values));
  }
  int64_t pattern_bytes = 0;
  for (const CurveTimingGroup& group : options.groups) {
    for (const std::string& id : group.ids) pattern_bytes += static_cast<int64_t>(id.size()) + 1;
  }
  const int64_t match_work = pattern_bytes * static_cast<int64_t>(set.curves.size());
  if (match_work > limits.max_values) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "timing_groups: ", pattern_bytes, " bytes of id patterns x ", set.curves.size(),
        " curves = ", match_work, " exceeds the server limit --max_values=", limits.max_values));
  }
  return absl::OkStatus();
}

// With a film grid finer than the curves' own rate, the timings have more frames than the
// clip: the grid's frames count against --max_values as the clip's do.
absl::Status CheckGridSize(const CurveSet& set, double timing_fps, const RequestLimits& limits) {
  const std::optional<FilmGrid> grid = FilmGrid::Make(set.fps, timing_fps);
  if (!grid) return absl::OkStatus();
  return CheckGridValues("curves", grid->GridFrameCount(set.frame_count), timing_fps,
                         static_cast<int64_t>(set.curves.size()), "curves", limits);
}

absl::Status CheckGroupModes(const v1::RetimeCurvesRequest& request) {
  for (int g = 0; g < request.timing_groups_size(); ++g) {
    const v1::CurveTimingGroupMode mode = request.timing_groups(g).mode();
    if (mode < v1::CURVE_TIMING_GROUP_MODE_UNSPECIFIED || mode > v1::GROUP_LIP_BLINK) {
      return absl::InvalidArgumentError(
          absl::StrCat("timing_groups[", g, "].mode: ", static_cast<int>(mode),
                       " is not a CurveTimingGroupMode (1 GROUP_STEP, 2 GROUP_KEEP, 3 "
                       "GROUP_LIP_BLINK)"));
    }
  }
  return absl::OkStatus();
}

// The request's given_timings -> options.given, by group name (docs/semantics.md, "A given
// timing"): each names a group of options.groups or the default group, not a GROUP_KEEP one,
// at most once, with one finite tau in [0, frame_count - 1] per counted frame.
absl::Status ConvertGivenTimings(const v1::RetimeCurvesRequest& request, const CurveSet& set,
                                 KomaUchiOptions& options) {
  if (request.given_timings_size() == 0) return absl::OkStatus();
  const std::optional<FilmGrid> grid = FilmGrid::Make(set.fps, options.timing_fps);
  const int counted = grid ? grid->GridFrameCount(set.frame_count) : set.frame_count;
  std::map<std::string, int> first_of;
  std::vector<std::vector<int>> members;  // per group, its curves: found once, when needed
  for (int i = 0; i < request.given_timings_size(); ++i) {
    const v1::GivenDrawingTiming& in = request.given_timings(i);
    const std::string path = absl::StrCat("given_timings[", i, "]");
    const std::string name = in.group().empty() ? std::string(kDefaultTimingGroupName) : in.group();
    if (name != kDefaultTimingGroupName) {
      const auto group = std::find_if(options.groups.begin(), options.groups.end(),
                                      [&name](const CurveTimingGroup& g) { return g.name == name; });
      if (group == options.groups.end()) {
        std::string names(kDefaultTimingGroupName);
        for (const CurveTimingGroup& g : options.groups) absl::StrAppend(&names, ", ", g.name);
        return absl::InvalidArgumentError(absl::StrCat(path, ".group: no timing group named \"",
                                                       name, "\" (the groups: ", names, ")"));
      }
      if (group->mode == TimingGroupMode::kKeep) {
        return absl::InvalidArgumentError(absl::StrCat(
            path, ".group: \"", name, "\" is a GROUP_KEEP group: its curves have no timing"));
      }
      // A named group no curve matched has no timing: the given one would vanish unseen.
      if (members.empty()) members = GroupMembers(options, set);
      if (members[static_cast<size_t>(group - options.groups.begin())].empty()) {
        return absl::InvalidArgumentError(
            absl::StrCat(path, ".group: \"", name, "\" has no curves in this request"));
      }
    }
    const auto [it, inserted] = first_of.emplace(name, i);
    if (!inserted) {
      return absl::InvalidArgumentError(absl::StrCat(path, ".group: \"", name,
                                                     "\" already has given_timings[", it->second,
                                                     "]"));
    }
    GivenGroupTiming given;
    given.taus.assign(in.source_frame().begin(), in.source_frame().end());
    given.exact_taus = in.exact_taus();
    KOMA_RETURN_IF_ERROR(
        CheckGivenGroupTiming(given, set.frame_count, counted, path + ".source_frame"));
    options.given.emplace(name, std::move(given));
  }
  return absl::OkStatus();
}

void FillTiming(const DrawingTiming& timing, v1::DrawingTiming* out) {
  out->set_frames_per_drawing(timing.frames_per_drawing);
  out->mutable_drawing_of_frame()->Add(timing.drawing_of_frame.begin(),
                                       timing.drawing_of_frame.end());
  out->mutable_source_frame()->Add(timing.source_frame.begin(), timing.source_frame.end());
  out->mutable_drawing_start()->Add(timing.drawing_start.begin(), timing.drawing_start.end());
  out->mutable_drawing_start_grid()->Add(timing.drawing_start_grid.begin(),
                                         timing.drawing_start_grid.end());
  out->mutable_drawing_source_frame()->Add(timing.drawing_tau.begin(), timing.drawing_tau.end());
  out->set_given(timing.given);
}

absl::Status CheckFinite(const KomaUchiResult& result) {
  for (size_t c = 0; c < result.curves.size(); ++c) {
    KOMA_RETURN_IF_ERROR(CheckEvaluatedFinite(result.curves[c].values, static_cast<int>(c)));
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<CurvesJob> ValidateCurvesRequest(const v1::RetimeCurvesRequest& request,
                                                const RequestLimits& limits) {
  if (!request.has_curves()) return absl::InvalidArgumentError("curves: required, not set");
  KOMA_RETURN_IF_ERROR(CheckGroupModes(request));
  CurvesJob job;
  KOMA_ASSIGN_OR_RETURN(job.set, CurveSetFromProto(request.curves(), "curves", limits));
  job.options = ConvertOptions(request);
  KOMA_RETURN_IF_ERROR(ConvertCurveOverrides(request, job.set, job.options));
  KOMA_RETURN_IF_ERROR(CheckGroupWork(job.set, job.options, limits));
  KOMA_RETURN_IF_ERROR(ValidateKomaUchiOptions(job.options, job.set));
  KOMA_RETURN_IF_ERROR(CheckGridSize(job.set, job.options.timing_fps, limits));
  KOMA_RETURN_IF_ERROR(ConvertGivenTimings(request, job.set, job.options));
  KOMA_ASSIGN_OR_RETURN(job.lip_blinks,
                        PrepareGroupLipBlinks(request, job.set, job.options, limits));
  return job;
}

absl::Status PrepareCurvesAnswer(const v1::RetimeCurvesRequest& request,
                                 const RequestLimits& limits, CurvesAnswer* answer) {
  if (CarriesFile(request)) {
    v1::RetimeCurvesRequest decoded;
    auto file = std::make_unique<CurveFile>();
    KOMA_RETURN_IF_ERROR(DecodeCurvesFile(request, limits, &decoded, file.get()));
    KOMA_RETURN_IF_ERROR(PrepareCurvesAnswer(decoded, limits, answer));
    answer->file = std::move(file);
    return absl::OkStatus();
  }
  KOMA_ASSIGN_OR_RETURN(CurvesJob job, ValidateCurvesRequest(request, limits));
  answer->set = std::move(job.set);
  answer->options = std::move(job.options);
  answer->lip_blinks = std::move(job.lip_blinks);
  return absl::OkStatus();
}

absl::Status CompleteCurvesAnswer(CurvesAnswer* answer) {
  answer->result = RetimeCurves(answer->set, answer->options);
  KOMA_RETURN_IF_ERROR(StopReason());  // stopped: some curves are unfinished (core/stop_check.h)
  KOMA_RETURN_IF_ERROR(DrawGroupLipBlinks(answer->lip_blinks, answer->result));
  answer->lip_blinks.clear();  // their copies of the groups' curves are not needed any more
  KOMA_RETURN_IF_ERROR(CheckFinite(answer->result));
  if (answer->file == nullptr) return absl::OkStatus();
  // As `koma curves` writes its output: every curve's values and stepped keys replace its own,
  // but a GROUP_KEEP curve's (timing -1), which stays as it came in.
  std::vector<std::optional<convert::CurveReplacement>> retimed;
  retimed.reserve(answer->result.curves.size());
  for (const RetimedCurve& curve : answer->result.curves) {
    if (curve.timing < 0) {
      retimed.emplace_back();
    } else {
      retimed.push_back(convert::CurveReplacement{curve.values, curve.steps});
    }
  }
  KOMA_ASSIGN_OR_RETURN(answer->file_field, CurvesFileField(*answer->file, std::move(retimed)));
  answer->file.reset();  // the parsed document is not needed any more
  return absl::OkStatus();
}

absl::Status RetimeCurvesAnswer(const v1::RetimeCurvesRequest& request, const RequestLimits& limits,
                                CurvesAnswer* answer) {
  KOMA_RETURN_IF_ERROR(PrepareCurvesAnswer(request, limits, answer));
  return CompleteCurvesAnswer(answer);
}

void FillCurvesResponse(const CurveSet& set, const KomaUchiResult& result,
                        v1::RetimeCurvesResponse* response) {
  response->mutable_key_frames()->Add(result.key_frames.begin(), result.key_frames.end());
  for (const DrawingTiming& timing : result.timings) FillTiming(timing, response->add_timings());
  for (size_t c = 0; c < result.curves.size(); ++c) {
    const RetimedCurve& in = result.curves[c];
    v1::RetimedCurve* out = response->add_curves();
    out->set_id(set.curves[c].id);
    out->set_timing(in.timing);
    out->mutable_values()->Add(in.values.begin(), in.values.end());
    out->mutable_stepped()->set_id(set.curves[c].id);
    convert::SteppedKeyframesToProto(in.steps, out->mutable_stepped());
    for (const auto& [length, drawings] : in.hold_histogram) {  // std::map: ascending
      v1::HoldCount* count = out->add_hold_histogram();
      count->set_length(length);
      count->set_drawings(drawings);
    }
    for (const KeyDrawing& key : in.keys) convert::KeyDrawingToProto(key, out->add_keys());
  }
  response->set_timing_fps(result.timing_fps);
  response->mutable_key_grid_frames()->Add(result.key_grid_frames.begin(),
                                           result.key_grid_frames.end());
  response->mutable_key_frames_merged()->Add(result.key_merged.begin(), result.key_merged.end());
  for (const TimingGroupResult& group : result.groups) {
    v1::CurveTimingGroupResult* out = response->add_timing_groups();
    out->set_name(group.name);
    out->mutable_curves()->Add(group.curves.begin(), group.curves.end());
    out->set_frames_per_drawing(group.frames_per_drawing);
    out->mutable_key_frames()->Add(group.key_frames.begin(), group.key_frames.end());
    out->mutable_key_grid_frames()->Add(group.key_grid_frames.begin(), group.key_grid_frames.end());
    out->mutable_key_frames_merged()->Add(group.key_merged.begin(), group.key_merged.end());
    out->set_timing(group.timing);
  }
}

absl::Status HandleRetimeCurves(const v1::RetimeCurvesRequest& request, const RequestLimits& limits,
                                v1::RetimeCurvesResponse* response) {
  CurvesAnswer answer;
  KOMA_RETURN_IF_ERROR(RetimeCurvesAnswer(request, limits, &answer));
  FillCurvesResponse(answer.set, answer.result, response);
  if (!answer.file_field.empty() && !response->MergeFromString(answer.file_field)) {
    return absl::InternalError("response: the file field does not parse");
  }
  return absl::OkStatus();
}

}  // namespace koma::server
