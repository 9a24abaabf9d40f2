#include "client/skeletal_summary.h"

#include <algorithm>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "client/files.h"

namespace koma::client {
namespace {

// "3-5, 9, 12-13": ascending integers as compact ranges; "none" when empty.
std::string Ranges(const std::vector<int>& sorted) {
  if (sorted.empty()) return "none";
  std::vector<std::string> parts;
  size_t i = 0;
  while (i < sorted.size()) {
    size_t j = i;
    while (j + 1 < sorted.size() && sorted[j + 1] == sorted[j] + 1) ++j;
    parts.push_back(i == j ? absl::StrCat(sorted[i]) : absl::StrCat(sorted[i], "-", sorted[j]));
    i = j + 1;
  }
  return absl::StrJoin(parts, ", ");
}

std::vector<int> OutputFramesOfKind(const v1::RetimeSkeletalResponse& response,
                                    v1::FrameKind kind) {
  std::vector<int> frames;
  for (int t = 0; t < response.kinds_size(); ++t) {
    if (response.kinds(t) == kind) frames.push_back(t);
  }
  return frames;
}

// Lengths of the runs of one drawing (one source frame) in output frames, in order.
std::vector<int> RunLengths(const v1::RetimeSkeletalResponse& response) {
  std::vector<int> runs;
  for (int t = 0; t < response.source_frames_size(); ++t) {
    if (t > 0 && response.source_frames(t) == response.source_frames(t - 1)) {
      ++runs.back();
    } else {
      runs.push_back(1);
    }
  }
  return runs;
}

int LongestRun(const v1::RetimeSkeletalResponse& response) {
  const std::vector<int> runs = RunLengths(response);
  return runs.empty() ? 0 : *std::max_element(runs.begin(), runs.end());
}

// With a film grid: the longest run of one drawing over the retimed grid sequence, in grid
// frames (max_hold's unit). Grid frame grid_frames[t] shows source_frames[t].
int LongestGridRun(const v1::RetimeSkeletalResponse& response) {
  int longest = 0;
  int run = 0;
  for (int t = 0; t < response.grid_frames_size(); ++t) {
    if (t > 0 && response.grid_frames(t) == response.grid_frames(t - 1)) continue;  // same g
    const bool same_drawing = t > 0 && response.source_frames(t) == response.source_frames(t - 1);
    run = same_drawing ? run + 1 : 1;
    longest = std::max(longest, run);
  }
  return longest;
}

// "(1 skipped; 4 later held over, now HELD; 1 later omitted)": what became of the duplicates
// that are not DUPLICATE output frames, so the line adds up; "" when nothing did.
std::string DuplicateFates(const v1::RetimeSkeletalResponse& response) {
  std::vector<std::string> fates;
  if (response.duplicates_skipped() > 0) {
    fates.push_back(absl::StrCat(response.duplicates_skipped(), " skipped"));
  }
  if (response.duplicates_held() > 0) {
    fates.push_back(absl::StrCat(response.duplicates_held(), " later held over, now HELD"));
  }
  if (response.duplicates_omitted() > 0) {
    fates.push_back(absl::StrCat(response.duplicates_omitted(), " later omitted"));
  }
  return fates.empty() ? "" : absl::StrCat(" (", absl::StrJoin(fates, "; "), ")");
}

// "8 drawings and 1 omission a second": the rates the server used (0: none).
std::string RatesText(const v1::RetimeSkeletalResponse& response) {
  std::vector<std::string> parts;
  if (response.drawings_per_second() > 0) {
    parts.push_back(absl::StrFormat("%g drawings", response.drawings_per_second()));
  }
  if (response.omissions_per_second() > 0) {
    parts.push_back(absl::StrFormat("%g omission%s", response.omissions_per_second(),
                                    response.omissions_per_second() == 1 ? "" : "s"));
  }
  return absl::StrCat(absl::StrJoin(parts, " and "), " a second");
}

bool AskedForCounts(const SkeletalArgs& args) {
  return args.omissions || args.holds || args.max_hold;
}
bool AskedForRates(const SkeletalArgs& args) {
  return args.omissions_per_second || args.drawings_per_second;
}

// Drawings a second of the output: its `drawings` (runs of one drawing) over its length
// (output frames of out_ms milliseconds each).
double DrawingsPerSecond(size_t drawings, const v1::RetimeSkeletalResponse& response,
                         double out_ms) {
  const int frames = response.source_frames_size();
  if (frames == 0 || out_ms <= 0) return 0.0;
  return static_cast<double>(drawings) / (frames * out_ms / 1000.0);
}

// Seconds per output frame: the motion's when returned, else what it would have been.
double OutputFrameTime(const SkeletalArgs& args, const SkeletalClip& clip,
                       const v1::RetimeSkeletalResponse& response) {
  if (response.has_motion() && response.motion().frame_time() > 0) {
    return response.motion().frame_time();
  }
  if (args.output_at_timing_rate && response.timing_fps() > 0) return 1.0 / response.timing_fps();
  return clip.frame_time;
}

}  // namespace

std::string SkeletalSummaryText(const SkeletalArgs& args, const SkeletalClip& clip,
                                const v1::RetimeSkeletalResponse& response) {
  const std::vector<int> deleted(response.deleted_frames().begin(),
                                 response.deleted_frames().end());
  const std::vector<int> hidden(response.hidden_frames().begin(), response.hidden_frames().end());
  const bool has_motion =
      response.has_motion() || !response.bvh_text().empty() || !response.gltf().empty() ||
      !response.fbx().empty();
  const std::string written = has_motion && !args.output.empty() && !args.timing_only
                                  ? OutputName(args.output)
                                  : "(timing only)";
  std::string text =
      absl::StrFormat("%s: %d frames, %zu joints, %.4g fps -> %s (%d frames)\n",
                      InputName(args.input), clip.frame_count, clip.skeleton.joints.size(),
                      1.0 / clip.frame_time, written, response.source_frames_size());
  for (const std::string& warning : response.warnings()) {
    absl::StrAppend(&text, "  warning    ", warning, "\n");
  }
  const bool grid = response.timing_fps() > 0;
  // Counts of the retiming are in grid frames with a film grid (docs/semantics.md).
  const char* unit = grid ? "grid frames" : "frames";
  if (response.timing_given()) {
    // --timing-from: no step ran; the sheet chose every drawing.
    absl::StrAppendFormat(
        &text, "  given      the timing of %s; source frames shown nowhere: %s\n",
        args.timing_from.empty() ? "the request" : InputName(args.timing_from), Ranges(deleted));
    const double out_ms = 1000.0 * OutputFrameTime(args, clip, response);
    const int longest = grid ? LongestGridRun(response) : LongestRun(response);
    const size_t drawings = RunLengths(response).size();
    absl::StrAppendFormat(&text, "  drawings   %zu shown, %.1f a second; longest hold %d %s\n",
                          drawings, DrawingsPerSecond(drawings, response, out_ms), longest, unit);
    if (!args.timing.empty()) {
      absl::StrAppend(&text, "  timing sheet: ", OutputName(args.timing), "\n");
    }
    return text;
  }
  absl::StrAppendFormat(&text, "  omitted    %3d inbetweens; source frames gone: %s\n",
                        response.omissions_applied(), Ranges(deleted));
  absl::StrAppendFormat(
      &text, "  duplicated %3d %s to keep the length%s; DUPLICATE at output frames %s\n",
      response.duplicates_applied(), unit, DuplicateFates(response),
      Ranges(OutputFramesOfKind(response, v1::DUPLICATE)));
  absl::StrAppendFormat(&text, "  held       %3d hold steps; HELD at output frames %s\n",
                        response.holds_applied(), Ranges(OutputFramesOfKind(response, v1::HELD)));
  absl::StrAppendFormat(&text, "                 source frames hidden by holds: %s\n",
                        Ranges(hidden));
  // Every number with its unit: the longest hold in max_hold's unit and in milliseconds.
  const double out_ms = 1000.0 * OutputFrameTime(args, clip, response);
  const int longest = grid ? LongestGridRun(response) : LongestRun(response);
  const double longest_ms = grid ? 1000.0 * longest / response.timing_fps() : longest * out_ms;
  absl::StrAppendFormat(&text,
                        "  longest hold %d %s (%.0f ms); requested omissions %d, holds %d, "
                        "max_hold %d %s\n",
                        longest, unit, longest_ms, response.omissions_requested(),
                        response.holds_requested(), response.max_hold(), unit);
  // What the viewer sees, and the rates that asked for it.
  const size_t drawings = RunLengths(response).size();
  absl::StrAppendFormat(&text, "  drawings   %zu shown, %.1f a second", drawings,
                        DrawingsPerSecond(drawings, response, out_ms));
  if (response.omissions_per_second() > 0 || response.drawings_per_second() > 0) {
    const bool defaults = !AskedForCounts(args) && !AskedForRates(args);
    absl::StrAppendFormat(
        &text, "; asked for %s%s", RatesText(response),
        defaults ? " (the anime defaults; --preset paper: the paper's counts)" : "");
  }
  absl::StrAppend(&text, "\n");
  if (response.timing_fps() > 0 && response.source_frames_size() > 0) {
    // What the grid did, in the units a viewer sees.
    std::vector<int> runs = RunLengths(response);
    std::sort(runs.begin(), runs.end());
    absl::StrAppendFormat(
        &text,
        "  film grid  %.4g fps: %d grid frames; %zu drawings shown %.0f-%.0f ms (median "
        "%.0f ms); the source showed each frame %.3g ms\n",
        response.timing_fps(), response.grid_source_frames_size(), runs.size(),
        runs.front() * out_ms, runs.back() * out_ms, runs[runs.size() / 2] * out_ms,
        1000.0 * clip.frame_time);
  }
  if (response.cut_frames_size() > 0) {
    const std::vector<int> cuts(response.cut_frames().begin(), response.cut_frames().end());
    absl::StrAppendFormat(&text,
                          "  cuts       %3d; shots retimed separately start at source frames 0, "
                          "%s\n",
                          response.cut_frames_size(), absl::StrJoin(cuts, ", "));
  }
  if (!args.timing.empty())
    absl::StrAppend(&text, "  timing sheet: ", OutputName(args.timing), "\n");
  return text;
}

nlohmann::json SkeletalSummaryJson(const SkeletalArgs& args, const SkeletalClip& clip,
                                   const v1::RetimeSkeletalResponse& response) {
  nlohmann::json j;
  j["input"] = args.input;
  j["outputs"] = nlohmann::json::object();
  if ((response.has_motion() || !response.bvh_text().empty()) && !args.timing_only &&
      !args.output.empty()) {
    j["outputs"]["motion"] = args.output;
  }
  if (!args.timing.empty()) j["outputs"]["timing"] = args.timing;
  if (!args.report.empty()) j["outputs"]["report"] = args.report;
  if (!args.xdts.empty()) j["outputs"]["xdts"] = args.xdts;
  if (!args.timing_from.empty()) j["timing_from"] = args.timing_from;
  j["input_frames"] = clip.frame_count;
  j["joints"] = clip.skeleton.joints.size();
  j["input_fps"] = 1.0 / clip.frame_time;
  j["output_frames"] = response.source_frames_size();
  j["output_fps"] = 1.0 / OutputFrameTime(args, clip, response);
  j["timing_fps"] = response.timing_fps();
  j["grid_frames"] = response.grid_source_frames_size();
  j["omissions_requested"] = response.omissions_requested();
  j["omissions_applied"] = response.omissions_applied();
  j["duplicates_applied"] = response.duplicates_applied();
  j["duplicates_skipped"] = response.duplicates_skipped();
  j["holds_requested"] = response.holds_requested();
  j["holds_applied"] = response.holds_applied();
  j["max_hold"] = response.max_hold();
  j["longest_hold"] = LongestRun(response);
  j["longest_hold_ms"] = LongestRun(response) * 1000.0 * OutputFrameTime(args, clip, response);
  j["duplicates_omitted"] = response.duplicates_omitted();
  j["duplicates_held"] = response.duplicates_held();
  j["deleted_frames"] =
      std::vector<int>(response.deleted_frames().begin(), response.deleted_frames().end());
  j["hidden_frames"] =
      std::vector<int>(response.hidden_frames().begin(), response.hidden_frames().end());
  j["duplicate_output_frames"] = OutputFramesOfKind(response, v1::DUPLICATE);
  j["held_output_frames"] = OutputFramesOfKind(response, v1::HELD);
  j["cut_frames"] = std::vector<int>(response.cut_frames().begin(), response.cut_frames().end());
  j["omissions_per_second"] = response.omissions_per_second();
  j["drawings_per_second"] = response.drawings_per_second();
  const size_t drawings = RunLengths(response).size();
  j["drawings_shown"] = drawings;
  j["drawings_shown_per_second"] =
      DrawingsPerSecond(drawings, response, 1000.0 * OutputFrameTime(args, clip, response));
  j["warnings"] = std::vector<std::string>(response.warnings().begin(), response.warnings().end());
  return j;
}

}  // namespace koma::client
