#include "client/cli_options.h"
#include "client/command_flags.h"

namespace koma::client {

CLI::App* AddSkeletalCommand(CLI::App& app, SkeletalArgs& args) {
  CLI::App* cmd =
      app.add_subcommand("skeletal", "Retime a BVH mocap clip into anime timing (RetimeSkeletal)");
  cmd->add_option("input", args.input,
                  "BVH or glTF file (.glb, .gltf, .vrm, .vrma) to retime; - reads standard input")
      ->required()
      ->type_name("IN.bvh|IN.glb");
  cmd->add_option("-o,--output", args.output,
                  "retimed file to write (BVH for a BVH input, the same glTF container for a glTF "
                  "one); - writes standard output")
      ->type_name("OUT.bvh|OUT.glb");
  cmd->add_option("--timing", args.timing,
                  "timing sheet CSV to write (output_frame,source_frame,kind,time_s); - writes "
                  "standard output")
      ->type_name("OUT.csv");
  cmd->add_flag("--timing-only", args.timing_only,
                "ask for no motion (return_motion false) and write only --timing and/or --xdts");
  AddReportFlag(cmd, &args.report);
  AddXdtsFlag(cmd, &args.xdts);
  cmd->add_option("--timing-from", args.timing_from,
                  "apply the timing of an edited sheet instead of computing one: an XDTS "
                  "(--xdts, edited in CLIP STUDIO PAINT, OpenToonz, TVPaint) or a --timing CSV; "
                  "cell N shows source frame N, a blank cell holds the frame before "
                  "(docs/usage.md)")
      ->type_name("SHEET.xdts|TIMING.csv");
  AddWholeNumber(cmd, "--omit,--omissions", &args.omissions, 0, INT32_MAX,
                 "Nio, inbetween omissions (nakanashi): frames removed where the motion is "
                 "fastest; a count turns the anime defaults off (the paper's: min(4, frames - 3))");
  AddWholeNumber(
      cmd, "--hold,--holds", &args.holds, 0, INT32_MAX,
      "Nhf, hold steps (koma-dori): frames that repeat their predecessor where the "
      "motion is stillest; a count turns the anime defaults off (the paper's: frames / 3)");
  AddNumber(cmd, "--omissions-per-second", &args.omissions_per_second, AtLeast(0),
            "omission rate: omissions per second of the clip (grid time), instead of --omit; "
            "scales with the take's length (40 s at 1.0: 40; default 1 unless a count is given)");
  AddNumber(cmd, "--drawings-per-second", &args.drawings_per_second, Above(0),
            "drawing rate: holds until the clip shows this many drawings a second (12 on "
            "twos, 8 on threes at 24 fps; default 8 unless a count is given); --max-hold "
            "defaults to the hold it needs");
  AddNumber(cmd, "--cut-neighbour-ratio", &args.cut_neighbour_ratio, AtLeast(0),
            "cuts: a jump at least this many times the SSD of the pairs around it splits the "
            "clip into shots retimed separately (default 20; 0: no cuts)");
  AddNumber(cmd, "--cut-median-ratio", &args.cut_median_ratio, AtLeast(0),
            "cuts: a jump's SSD must also be above this many times the clip's median "
            "(default 20)");
  AddWholeNumber(cmd, "--max-hold", &args.max_hold, 1, INT32_MAX,
                 "longest run of one drawing, in frames (grid frames with a film grid; default "
                 "the drawing rate's, 3 'on threes'); a count: the paper's algorithm");
  cmd->add_flag("--keep-length,!--no-keep-length", args.keep_length,
                "re-insert a duplicate after each omission so the clip keeps its length "
                "(default); --no-keep-length: the clip gets shorter by the omissions");
  AddChoice(cmd, "--order", &args.order, {"omit-then-hold", "hold-then-omit"},
            "which step runs first (default omit-then-hold, the paper's)");
  cmd->add_flag("--hold-first", args.hold_first, "same as --order hold-then-omit");
  AddStringList(cmd, "--joint-weights", &args.joint_weights,
                "weights of the joints in the speed measure, >= 0: one per joint in file order "
                "(1,1,0.5,...) or NAME=W for some (Hips=0,Head=2; the others 1)")
      ->type_name("W,...|NAME=W,...");
  cmd->add_flag("--root-relative", args.root_relative,
                "measure speed relative to the root joint (ignore locomotion)");
  AddNumberList(cmd, "--camera", &args.camera, {}, 16,
                "4x4 view-projection matrix, 16 numbers column-major (OpenGL/glTF): measure "
                "speed on screen");
  AddBool(cmd, "--return-motion", &args.return_motion,
          "ask for the retimed motion (default true; false: the timing map only, needs "
          "--timing)");
  AddTimingFpsFlag(cmd, &args.timing_fps, "the drawings are", "the BVH's");
  cmd->add_option_function<std::string>(
         "--output-rate",
         [&args](const std::string& rate) {
           if (rate != "source" && rate != "timing") {
             throw FlagValueError("--output-rate: \"" + rate + "\" is not one of source, timing");
           }
           args.output_at_timing_rate = rate == "timing";
         },
         "source (default: the BVH's rate and length) or timing (one frame per grid frame)")
      ->type_name("source|timing")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  AddSendFileFlag(cmd, &args.send_file, "bvh_text");
  // glTF inputs (.glb, .gltf, .vrm, .vrma): the file travels whole in `gltf`.
  AddStringList(cmd, "--gltf-animations,--animation", &args.animations,
                "glTF: the animations to retime, by name or index, comma-separated or repeated "
                "(default every animation, each on its own)")
      ->type_name("NAME|INDEX,...");
  cmd->add_flag("--gltf-retime-none", args.retime_none,
                "glTF: retime no animation (the file comes back as it was)");
  AddNumber(cmd, "--gltf-source-fps", &args.source_fps, NumberBounds{0, 1000, false, false},
            "glTF: frames per second the animations are sampled at (default or 0: the keys' "
            "spacing where dense, else 30)");
  AddChoice(cmd, "--gltf-keys", &args.gltf_keys, {"step", "linear"},
            "glTF: step (default: a STEP key where each drawing starts) or linear (a LINEAR key "
            "per output frame, for players that mishandle STEP)");
  cmd->add_flag("--gltf-keep-original", args.keep_original,
                "glTF: keep each animation and add the retimed one as \"<name>.anime\"");
  // FBX inputs (.fbx): the file travels whole in `fbx`.
  cmd->add_option("--fbx-take,--take", args.take,
                  "FBX: the take (AnimationStack) to retime (default: the file's current take)")
      ->type_name("NAME");
  AddPresetFlag(cmd);
  AddCommonFlags(cmd, &args, "60");
  return cmd;
}

}  // namespace koma::client
