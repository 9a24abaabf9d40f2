#include "client/cli_options.h"
#include "client/command_flags.h"

namespace koma::client {

CLI::App* AddCurvesCommand(CLI::App& app, CurvesArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "curves", "Draw animation curves on twos/threes with tame/tsume (RetimeCurves)");
  cmd->add_option("input", args.input,
                  "motion3.json, or CSV (frame,<id>,... per frame); - reads standard input")
      ->required()
      ->type_name("IN");
  cmd->add_option("-o,--output", args.output,
                  "motion3.json or .csv to write; - writes standard output (in the input's "
                  "format, or --format)")
      ->type_name("OUT");
  cmd->add_option("--timing", args.timing,
                  "drawing sheet CSV to write (output_frame,drawing,source_frame,time_s); - "
                  "writes standard output")
      ->type_name("OUT.csv");
  cmd->add_flag("--timing-only", args.timing_only, "write only the --timing sheet, no curves");
  cmd->add_option("--report", args.report,
                  "before/after HTML report to write, one self-contained file (docs/report.md)")
      ->type_name("OUT.html");
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
  AddNumberWithDefault(cmd, "--fps", &args.csv_fps, Above(0),
                       "frames per second of a CSV input (default 30)")
      ->type_name("FPS");
  AddNumber(cmd, "--timing-fps", &args.timing_fps, {},
            "film grid the drawings are counted on, frames per second (default 24; 0 = count "
            "in the input's own frames; at most 1000)")
      ->type_name("FPS");
  AddChoice(cmd, "--format", &args.format, {"motion3", "csv"},
            "format of the output -o - (default: the input's; an input's format is read from its "
            "contents)");
  cmd->add_flag("--send-file", args.send_file,
                "send the input file as is (motion3_json or csv_text, csv_fps = --fps) for the "
                "server to parse, instead of the "
                "decoded data; the outputs are the same bytes");
  AddPresetFlag(cmd);
  AddCommonFlags(cmd, &args.server, &args.deadline_seconds, &args.json, &args.quiet, "60");
  return cmd;
}

}  // namespace koma::client
