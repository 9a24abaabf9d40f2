#include "client/curves_command.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/strings/match.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "client/channel.h"
#include "client/command_output.h"
#include "client/curves_convert.h"
#include "client/curves_summary.h"
#include "client/files.h"
#include "client/flag_values.h"
#include "client/report/curves_report.h"
#include "client/xdts_sheets.h"
#include "formats/xdts.h"
#include "client/retime_call.h"
#include "client/spine_curves.h"
#include "client/timing_from_curves.h"
#include "core/timing_groups.h"
#include "formats/drawing_sheet.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

// "ParamHair=2" -> request.curve_overrides.
absl::Status AddCurveOverrides(const std::vector<std::string>& entries,
                               v1::RetimeCurvesRequest& request) {
  for (const std::string& entry : entries) {
    const size_t equals = entry.rfind('=');
    if (equals == std::string::npos || equals == 0) {
      return absl::InvalidArgumentError(
          absl::StrCat("--curve-on: \"", entry, "\" is not ID=N, e.g. ParamHair=2"));
    }
    absl::StatusOr<int64_t> n =
        ParseWholeNumber("--curve-on", entry.substr(equals + 1), 1, INT32_MAX);
    if (!n.ok()) return n.status();
    v1::CurveOverride* o = request.add_curve_overrides();
    o->set_curve_id(entry.substr(0, equals));
    o->set_frames_per_drawing(static_cast<int>(*n));
  }
  return absl::OkStatus();
}

// --group / --group-on / --no-default-groups -> request.timing_groups (the default grouping
// spelt out when --group-on changes one of its groups).
// The group of a --group-on / --group-mode entry "NAME=VALUE" (`example` shows one), and VALUE.
absl::StatusOr<std::pair<TimingGroupFlag*, std::string>> GroupEntry(
    const std::string& flag, const std::string& entry, const char* example,
    std::vector<TimingGroupFlag>& groups) {
  const size_t equals = entry.rfind('=');
  if (equals == std::string::npos || equals == 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(flag, ": \"", entry, "\" is not NAME=", example));
  }
  const std::string name = entry.substr(0, equals);
  auto it = std::find_if(groups.begin(), groups.end(),
                         [&name](const TimingGroupFlag& g) { return g.name == name; });
  if (it == groups.end()) {
    std::string names;
    for (const TimingGroupFlag& g : groups) absl::StrAppend(&names, names.empty() ? "" : ", ", g.name);
    return absl::InvalidArgumentError(absl::StrCat(
        flag, ": no timing group \"", name, "\" (groups: ", names.empty() ? "none" : names,
        name == kDefaultTimingGroupName ? "; body is --on" : "", ")"));
  }
  return std::make_pair(&*it, entry.substr(equals + 1));
}

absl::Status AddTimingGroups(const CurvesArgs& args, v1::RetimeCurvesRequest& request) {
  std::vector<TimingGroupFlag> groups = args.groups;
  if (groups.empty() && (!args.group_on.empty() || !args.group_mode.empty()) &&
      !!args.default_groups) {
    for (const CurveTimingGroup& g : DefaultLive2dTimingGroups()) {
      groups.push_back(
          {g.name, g.ids, std::nullopt, std::nullopt, std::nullopt, {},
           convert::TimingGroupModeToProto(g.mode), {}, {}, "", std::nullopt});
    }
  }
  for (const std::string& entry : args.group_on) {
    absl::StatusOr<std::pair<TimingGroupFlag*, std::string>> group =
        GroupEntry("--group-on", entry, "N, e.g. hair=2", groups);
    if (!group.ok()) return group.status();
    absl::StatusOr<int64_t> n =
        ParseWholeNumber("--group-on " + group->first->name, group->second, 1, INT32_MAX);
    if (!n.ok()) return n.status();
    group->first->frames_per_drawing = static_cast<int>(*n);
  }
  for (const std::string& entry : args.group_mode) {
    absl::StatusOr<std::pair<TimingGroupFlag*, std::string>> group =
        GroupEntry("--group-mode", entry, "MODE, e.g. face=keep", groups);
    if (!group.ok()) return group.status();
    absl::StatusOr<v1::CurveTimingGroupMode> mode =
        ParseGroupMode("--group-mode " + group->first->name, group->second);
    if (!mode.ok()) return mode.status();
    group->first->mode = *mode;
  }
  for (const TimingGroupFlag& flag : groups) {
    v1::CurveTimingGroup* g = request.add_timing_groups();
    g->set_name(flag.name);
    for (const std::string& id : flag.ids) g->add_ids(id);
    if (flag.frames_per_drawing) g->set_frames_per_drawing(*flag.frames_per_drawing);
    if (flag.tame) g->set_tame(*flag.tame);
    if (flag.tsume) g->set_tsume(*flag.tsume);
    for (int key : flag.key_frames) g->add_key_frames(key);
    if (flag.mode != v1::CURVE_TIMING_GROUP_MODE_UNSPECIFIED) g->set_mode(flag.mode);
    for (const std::string& id : flag.mouth_ids) g->mutable_mouth()->add_ids(id);
    if (!flag.mouth_mode.empty()) {
      g->mutable_mouth()->set_mode(flag.mouth_mode == "follow" ? v1::MOUTH_FOLLOW : v1::MOUTH_RANDOM);
    }
    for (const std::string& id : flag.eye_ids) g->mutable_eyes()->add_ids(id);
    if (flag.seed) g->set_seed(*flag.seed);
  }
  if (!args.default_groups) request.set_default_timing_groups(false);
  return absl::OkStatus();
}

// "on=2,tame=1.5" of --segment-overrides or --group into out's n, tame and tsume; false when a
// setting is not KEY=VALUE with a known KEY (the caller reports the usage).
template <typename Settings>
absl::StatusOr<bool> ParseDrawingSettings(const std::string& flag_name, const std::string& text,
                                          Settings& out) {
  for (absl::string_view setting : absl::StrSplit(text, ',')) {
    const std::vector<std::string> kv = absl::StrSplit(setting, absl::MaxSplits('=', 1));
    if (kv.size() != 2) return false;
    const std::string& key = kv[0];
    const std::string flag = absl::StrCat(flag_name, " ", key);
    if (key == "on" || key == "frames-per-drawing" || key == "frames_per_drawing") {
      absl::StatusOr<int64_t> n = ParseWholeNumber(flag, kv[1], 1);
      if (!n.ok()) return n.status();
      out.frames_per_drawing = static_cast<int>(*n);
    } else if (key == "tame" || key == "tsume") {
      absl::StatusOr<double> s = ParseNumber(flag, kv[1], AtLeast(1));
      if (!s.ok()) return s.status();
      (key == "tame" ? out.tame : out.tsume) = *s;
    } else {
      return false;
    }
  }
  return true;
}

}  // namespace

absl::StatusOr<v1::CurveTimingGroupMode> ParseGroupMode(const std::string& flag,
                                                        const std::string& text) {
  if (text == "step") return v1::GROUP_STEP;
  if (text == "keep") return v1::GROUP_KEEP;
  if (text == "lipblink" || text == "lip-blink" || text == "lip_blink") return v1::GROUP_LIP_BLINK;
  return absl::InvalidArgumentError(
      absl::StrCat(flag, ": \"", text, "\" is not a group mode (step, keep or lipblink)"));
}

absl::StatusOr<TimingGroupFlag> ParseTimingGroup(const std::string& text) {
  constexpr char kFlag[] = "--group";
  const std::string usage = absl::StrCat(
      kFlag, ": \"", text,
      "\" is not NAME=ID,...[:on=N,tame=S,tsume=S,keys=F/F/...,mode=step|keep|lipblink,"
      "mouth=ID/ID,eyes=ID/ID,mouth-mode=random|follow,seed=N], e.g. "
      "hair=ParamHair*,ParamBust*:on=2");
  const size_t equals = text.find('=');
  if (equals == std::string::npos || equals == 0) return absl::InvalidArgumentError(usage);
  TimingGroupFlag out;
  out.name = text.substr(0, equals);
  const size_t colon = text.find(':', equals);
  const std::string ids = text.substr(equals + 1, colon == std::string::npos ? std::string::npos
                                                                              : colon - equals - 1);
  for (absl::string_view id : absl::StrSplit(ids, ',')) {
    if (id.empty()) return absl::InvalidArgumentError(usage);
    out.ids.emplace_back(id);
  }
  if (colon != std::string::npos) {
    // keys=F/F/F (the group's named key poses; '/' since ',' separates the settings), then
    // on, tame and tsume as for --segment-overrides.
    std::vector<std::string> settings;
    for (absl::string_view setting : absl::StrSplit(text.substr(colon + 1), ',')) {
      if (absl::StartsWith(setting, "mode=")) {
        absl::StatusOr<v1::CurveTimingGroupMode> mode =
            ParseGroupMode(absl::StrCat(kFlag, " mode"), std::string(setting.substr(5)));
        if (!mode.ok()) return mode.status();
        out.mode = *mode;
        continue;
      }
      // LipBlink's settings of a lipblink group (the server refuses them in other modes).
      if (absl::StartsWith(setting, "mouth=") || absl::StartsWith(setting, "eyes=")) {
        const size_t eq = setting.find('=');
        std::vector<std::string>& drawn = setting[0] == 'm' ? out.mouth_ids : out.eye_ids;
        for (absl::string_view id : absl::StrSplit(setting.substr(eq + 1), '/')) {
          if (id.empty()) return absl::InvalidArgumentError(usage);
          drawn.emplace_back(id);
        }
        continue;
      }
      if (absl::StartsWith(setting, "mouth-mode=")) {
        out.mouth_mode = std::string(setting.substr(11));
        if (out.mouth_mode != "random" && out.mouth_mode != "follow") {
          return absl::InvalidArgumentError(absl::StrCat(
              kFlag, " mouth-mode: \"", out.mouth_mode, "\" is not random or follow"));
        }
        continue;
      }
      if (absl::StartsWith(setting, "seed=")) {
        absl::StatusOr<uint64_t> seed =
            ParseUnsigned64(absl::StrCat(kFlag, " seed"), setting.substr(5));
        if (!seed.ok()) return seed.status();
        out.seed = *seed;
        continue;
      }
      if (!absl::StartsWith(setting, "keys=")) {
        settings.emplace_back(setting);
        continue;
      }
      for (absl::string_view key : absl::StrSplit(setting.substr(5), '/')) {
        absl::StatusOr<int64_t> frame =
            ParseWholeNumber(absl::StrCat(kFlag, " keys"), std::string(key), 0, INT32_MAX);
        if (!frame.ok()) return frame.status();
        out.key_frames.push_back(static_cast<int>(*frame));
      }
    }
    if (!settings.empty()) {
      absl::StatusOr<bool> known = ParseDrawingSettings(kFlag, absl::StrJoin(settings, ","), out);
      if (!known.ok()) return known.status();
      if (!*known) return absl::InvalidArgumentError(usage);
    }
  }
  return out;
}

absl::StatusOr<SegmentOverrideFlag> ParseSegmentOverride(const std::string& text) {
  constexpr char kFlag[] = "--segment-overrides";
  const std::string usage = absl::StrCat(
      kFlag, ": \"", text,
      "\" is not SEG:KEY=VALUE,... with KEY on (frames per drawing), tame or tsume, e.g. "
      "1:on=2,tame=1.5");
  const size_t colon = text.find(':');
  if (colon == std::string::npos) return absl::InvalidArgumentError(usage);
  SegmentOverrideFlag out;
  absl::StatusOr<int64_t> segment = ParseWholeNumber(kFlag, text.substr(0, colon), 0);
  if (!segment.ok()) return segment.status();
  out.segment = static_cast<int>(*segment);
  const std::string rest = text.substr(colon + 1);
  if (rest.empty()) return absl::InvalidArgumentError(usage);
  absl::StatusOr<bool> known = ParseDrawingSettings(kFlag, rest, out);
  if (!known.ok()) return known.status();
  if (!*known) return absl::InvalidArgumentError(usage);
  return out;
}

absl::StatusOr<v1::RetimeCurvesRequest> BuildCurvesRequest(const CurvesArgs& args,
                                                           const CurveSet& curves) {
  v1::RetimeCurvesRequest request;
  *request.mutable_curves() = CurveSetToProto(curves);
  request.mutable_key_frames()->Add(args.keys.begin(), args.keys.end());
  if (args.frames_per_drawing) request.set_frames_per_drawing(*args.frames_per_drawing);
  if (args.tame) request.set_tame(*args.tame);
  if (args.tsume) request.set_tsume(*args.tsume);
  if (absl::Status s = AddCurveOverrides(args.curve_on, request); !s.ok()) return s;
  for (const SegmentOverrideFlag& flag : args.segment_overrides) {
    v1::SegmentOverride* o = request.add_segment_overrides();
    o->set_segment(flag.segment);
    if (flag.frames_per_drawing) o->set_frames_per_drawing(*flag.frames_per_drawing);
    if (flag.tame) o->set_tame(*flag.tame);
    if (flag.tsume) o->set_tsume(*flag.tsume);
  }
  if (args.timing_fps) request.set_timing_fps(*args.timing_fps);
  if (!args.merge_key_poses) request.set_merge_key_poses(false);
  if (absl::Status s = AddTimingGroups(args, request); !s.ok()) return s;
  return request;
}

absl::StatusOr<v1::RetimeCurvesRequest> BuildCurvesFileRequest(const CurvesArgs& args,
                                                               const CurveInput& input) {
  if (input.spine) {
    CurveInput selected = input;
    if (selected.spine_animation < 0) {
      if (absl::Status s = SelectOneSpineAnimation(selected, args.animations); !s.ok()) return s;
    }
    absl::StatusOr<v1::RetimeCurvesRequest> request = BuildCurvesRequest(args, selected.curves);
    if (request.ok() && args.send_file) {
      request->clear_curves();
      request->set_spine_json(selected.text);
      request->set_spine_animation(selected.spine->animations[selected.spine_animation].name);
    }
    return request;
  }
  absl::StatusOr<v1::RetimeCurvesRequest> request = BuildCurvesRequest(args, input.curves);
  if (request.ok() && args.send_file) PutCurveFile(args, input, &*request);
  return request;
}

absl::Status CheckCurvesFlags(const CurvesArgs& args) {
  if (args.timing_only && args.timing.empty() && args.xdts.empty()) {
    return absl::InvalidArgumentError(
        "--timing-only needs --timing OUT.csv or --xdts OUT.xdts (the sheet it writes)");
  }
  if (args.timing_only && !args.output.empty()) {
    return absl::InvalidArgumentError("-o: --timing-only writes only the sheet; drop -o");
  }
  if (!args.timing_only && args.output.empty()) {
    return absl::InvalidArgumentError(
        "-o/--output OUT.motion3.json or OUT.csv is required (or --timing-only with --timing "
        "OUT.csv)");
  }
  return CheckOneOnStdout({{"-o", args.output},
                           {"--timing", args.timing},
                           {"--report", args.report},
                           {"--xdts", args.xdts}},
                          args.json);
}

absl::Status WriteCurvesOutputs(const CurvesArgs& args, const CurveInput& input,
                                const v1::RetimeCurvesResponse& response) {
  if (!args.timing_only) {
    std::vector<std::optional<CurveReplacement>> replacements;
    for (const v1::RetimedCurve& curve : response.curves()) {
      // A GROUP_KEEP curve (timing -1) stays as it came in.
      if (curve.timing() < 0) {
        replacements.emplace_back();
      } else {
        replacements.push_back(convert::ReplacementFromProto(curve));
      }
    }
    if (replacements.size() != input.curves.curves.size()) {
      return absl::InternalError(absl::StrCat("the server answered ", replacements.size(),
                                              " curves for ", input.curves.curves.size()));
    }
    if (absl::Status s =
            WriteCurveOutput(args.output, input, replacements, CurveFormatFromFlag(args.format));
        !s.ok()) {
      return s;
    }
  }
  if (!args.timing.empty() && response.timings_size() > 0) {
    // One track per timing group (the default group's first), each at its own n.
    std::vector<DrawingTiming> timings;
    std::vector<std::string> names;
    std::vector<int> indices;  // of the timings in the response
    if (response.timing_groups_size() == 0) {
      timings.push_back(TimingFromProto(response.timings(0)));
      names.emplace_back(kDefaultTimingGroupName);
      indices.push_back(0);
    }
    for (const v1::CurveTimingGroupResult& group : response.timing_groups()) {
      if (group.curves_size() == 0 || group.frames_per_drawing() == 0) continue;  // no drawings
      if (group.timing() < 0 || group.timing() >= response.timings_size()) {
        return absl::InternalError(absl::StrCat("the server answered timing group \"",
                                                group.name(), "\" with timing ", group.timing()));
      }
      timings.push_back(TimingFromProto(response.timings(group.timing())));
      names.push_back(group.name());
      indices.push_back(group.timing());
    }
    std::vector<formats::DrawingSheetTrack> tracks;
    for (size_t k = 0; k < timings.size(); ++k) {
      tracks.push_back({names[k], &timings[k], convert::KeysByDrawing(response, indices[k])});
    }
    const std::string sheet = formats::WriteGroupedDrawingSheetCsv(tracks, input.curves.fps);
    if (absl::Status s = WriteFile(args.timing, sheet); !s.ok()) return s;
  }
  if (!args.xdts.empty()) {
    absl::StatusOr<formats::XdtsSheet> sheet =
        CurvesXdtsSheet(response, XdtsClipName(args.input, args.xdts));
    if (!sheet.ok()) return sheet.status();
    if (absl::Status s = WriteFile(args.xdts, formats::WriteXdts(*sheet)); !s.ok()) return s;
  }
  return absl::OkStatus();
}

int RunCurves(const CurvesArgs& args) {
  const CommandOutput out("curves", args.json, args.quiet, args.server);
  if (absl::Status s = CheckCurvesFlags(args); !s.ok()) return out.UsageFailure(s);
  absl::StatusOr<CurveInput> input =
      ReadCurveInput(args.input, args.csv_fps, CurveFormat::kAuto, "curves");
  if (!input.ok()) return out.Failure(input.status());
  if (input->spine && !args.timing_from.empty()) {
    return out.UsageFailure(absl::InvalidArgumentError(
        absl::StrCat("--timing-from: not for a Spine skeleton (", InputName(args.input), ")")));
  }
  if (input->spine) return RunSpineCurves(args, *input, out);
  if (!args.animations.empty()) {
    return out.UsageFailure(absl::InvalidArgumentError(
        absl::StrCat("--animation: ", args.input, " is not a Spine skeleton")));
  }
  if (!args.timing_only) {
    absl::StatusOr<CurveFormat> format =
        CurveOutputFormat(args.output, CurveFormatFromFlag(args.format), *input);
    if (!format.ok()) return out.UsageFailure(format.status());
  }
  absl::StatusOr<v1::RetimeCurvesRequest> request = BuildCurvesRequest(args, input->curves);
  if (!request.ok()) return out.UsageFailure(request.status());
  // --send-file: the wire carries the file; the report still reads the decoded request.
  std::optional<v1::RetimeCurvesRequest> file_request;
  if (args.send_file) {
    absl::StatusOr<v1::RetimeCurvesRequest> with_file = BuildCurvesFileRequest(args, *input);
    if (!with_file.ok()) return out.UsageFailure(with_file.status());
    file_request = *std::move(with_file);
  }
  if (absl::Status s = CheckWritable({args.output, args.timing, args.report, args.xdts}); !s.ok())
    return out.Failure(s);

  v1::RetimeCurvesResponse response;
  if (!args.timing_from.empty()) {
    // The sheet's cells name the drawings of koma's own answer: ask for it, then give the
    // sheet's timing (docs/usage.md, "Timing from an edited sheet").
    if (int code = CallRetime(args, out, &v1::Retime::Stub::RetimeCurves,
                              file_request ? *file_request : *request, &response);
        code >= 0) {
      return code;
    }
    const std::string name = XdtsClipName(args.input, args.timing_from);
    for (v1::RetimeCurvesRequest* r : {&*request, file_request ? &*file_request : nullptr}) {
      if (r == nullptr) continue;
      if (absl::Status s = SetCurvesTimingFrom(args.timing_from, name, response, r, nullptr);
          !s.ok()) {
        return out.Failure(s);
      }
    }
    response.Clear();
  }
  if (int code = CallRetime(args, out, &v1::Retime::Stub::RetimeCurves,
                            file_request ? *file_request : *request, &response);
      code >= 0) {
    return code;
  }

  if (absl::Status s = WriteCurvesOutputs(args, *input, response); !s.ok()) return out.Failure(s);
  if (!args.report.empty()) {
    if (absl::Status s = report::WriteCurvesReport(args.report, *request, response, args.input);
        !s.ok()) {
      return out.Failure(s);
    }
  }
  out.Success(CurvesSummaryText(args, input->curves, *request, response) + TimingFromLine(args.timing_from) +
                  XdtsLine(args.xdts) +
                  ReportLine(args.report),
              CurvesSummaryJson(args, input->curves, *request, response),
              IsStdio(args.output) || IsStdio(args.timing) || IsStdio(args.report) ||
                  IsStdio(args.xdts));
  return kExitOk;
}

}  // namespace koma::client
