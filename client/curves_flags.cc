#include "client/cli_options.h"
#include "client/command_flags.h"
#include "client/curves_command.h"

namespace koma::client {

CLI::App* AddCurvesCommand(CLI::App& app, CurvesArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "curves", "Draw animation curves on twos/threes with tame/tsume (RetimeCurves)");
  AddCurveInputFlag(cmd, &args.input);
  cmd->add_option("-o,--output", args.output,
                  "motion3.json or .csv to write; - writes standard output (in the input's "
                  "format, or --format)")
      ->type_name("OUT");
  cmd->add_option("--timing", args.timing,
                  "drawing sheet CSV to write (output_frame,drawing,source_frame,time_s); - "
                  "writes standard output")
      ->type_name("OUT.csv");
  cmd->add_flag("--timing-only", args.timing_only,
                "write only the sheets (--timing, --xdts), no curves");
  AddReportFlag(cmd, &args.report);
  AddXdtsFlag(cmd, &args.xdts);
  AddWholeNumber(cmd, "--on,--frames-per-drawing", &args.frames_per_drawing, 1, INT32_MAX,
                 "koma-uchi: frames each drawing is held, 2 'on twos', 3 'on threes' (grid "
                 "frames with a film grid; default 3)");
  AddWholeNumberList(cmd, "--keys,--key-frames", &args.keys, 0, INT32_MAX,
                     "key poses (genga) in frames, e.g. 0,10,25 (default: the keyframe times)");
  AddNumber(cmd, "--tame", &args.tame, AtLeast(1),
            "tame strength >= 1: drawings bunch near the first key of each segment, a slow "
            "start (default 1, even spacing)");
  AddNumber(cmd, "--tsume", &args.tsume, AtLeast(1),
            "tsume strength >= 1: drawings bunch near the next key, a slow arrival (default 1)");
  AddStringList(cmd, "--curve-on,--curve-overrides", &args.curve_on,
                "ID=N: this curve held N frames per drawing (hair on twos while the body is on "
                "threes); repeatable or comma-separated")
      ->type_name("ID=N,...");
  cmd->add_option_function<std::vector<std::string>>(
         "--segment-overrides",
         [&args](const std::vector<std::string>& values) {
           args.segment_overrides.clear();
           for (const std::string& value : values) {
             absl::StatusOr<SegmentOverrideFlag> parsed = ParseSegmentOverride(value);
             if (!parsed.ok()) ThrowFlagError(parsed.status());
             args.segment_overrides.push_back(*parsed);
           }
         },
         "SEG:on=N,tame=S,tsume=S: settings of the segment between key poses SEG and SEG+1 "
         "(0-based); repeatable")
      ->type_name("SEG:KEY=V,...")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  AddStringList(cmd, "--animation,--spine-animation", &args.animations,
                "Spine skeleton: the animation to retime (repeatable; default every animation "
                "with bone keys)")
      ->type_name("NAME");
  cmd->add_flag("--merge-key-poses,!--no-merge-keys", args.merge_key_poses,
                "keyframes closer than a drawing form one key pose, so no drawing is shorter "
                "than --on (default); --no-merge-keys: every keyframe time is a key pose");
  cmd->add_option_function<std::vector<std::string>>(
         "--group,--timing-groups",
         [&args](const std::vector<std::string>& values) {
           args.groups.clear();
           for (const std::string& value : values) {
             absl::StatusOr<TimingGroupFlag> parsed = ParseTimingGroup(value);
             if (!parsed.ok()) ThrowFlagError(parsed.status());
             args.groups.push_back(*parsed);
           }
         },
         "NAME=ID,...[:on=N,tame=S,tsume=S,keys=F/F/...,mode=M,...]: a timing group, its curves "
         "by id or pattern (ParamHair*) timed on their own key poses; mode step (default), keep "
         "or lipblink (with mouth=ID/ID, eyes=ID/ID, mouth-mode=random|follow, seed=N); "
         "repeatable, the first match wins; replaces the default groups (face in mode lipblink, "
         "hair; the rest is body)")
      ->type_name("NAME=IDS[:KEY=V,...]")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  AddStringList(cmd, "--group-on", &args.group_on,
                "NAME=N: frames per drawing of a timing group (of --group, or the default face "
                "and hair); repeatable or comma-separated")
      ->type_name("NAME=N,...");
  AddStringList(cmd, "--group-mode", &args.group_mode,
                "NAME=MODE: a timing group's mode (of --group, or the default face and hair): "
                "step (koma-uchi), keep (its curves as they came in) or lipblink (LipBlink's "
                "mouth flaps and blinks, the rest stepped; the default face's); repeatable")
      ->type_name("NAME=MODE,...");
  cmd->add_flag("--default-timing-groups,!--no-default-groups", args.default_groups,
                "without --group, Live2D's standard ids in the groups face and hair, the rest "
                "body (default); --no-default-groups: every curve on the same key poses");
  cmd->add_flag("--check-keys", args.check_keys,
                "measure the answer against the input's keys: keyed extremes and ends not drawn "
                "(within 3 frames and 0.5% of the curve's range) and drawings a second; printed "
                "after the summary and in --json's key_check");
  AddCurveFileFlags(cmd, args, "the drawings are");
  return cmd;
}

}  // namespace koma::client
