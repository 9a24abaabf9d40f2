#include "client/cli_options.h"
#include "client/command_flags.h"

namespace koma::client {

CLI::App* AddLipBlinkCommand(CLI::App& app, LipBlinkArgs& args) {
  CLI::App* cmd =
      app.add_subcommand("lipblink", "Three-drawing mouth flaps and anime blinks (LipBlink)");
  cmd->add_option("input", args.input,
                  "motion3.json, CSV (frame,<id>,... per frame) or a Spine skeleton JSON; - reads "
                  "standard input "
                  "(optional with --audio or --rhubarb)")
      ->type_name("IN");
  cmd->add_option("-o,--output", args.output,
                  "motion3.json or .csv to write; - writes standard output")
      ->type_name("OUT");
  AddReportFlag(cmd, &args.report);
  AddXdtsFlag(cmd, &args.xdts);
  // mouth
  AddStringList(cmd, "--mouth,--mouth-ids", &args.mouth_ids,
                "mouth-open curve ids (default ParamMouthOpenY)");
  AddChoice(cmd, "--mode,--mouth-mode", &args.mode, {"random", "follow"},
            "random (the paper: uniform between the allowed shapes) or follow the input "
            "(default random)");
  AddWholeNumber(cmd, "--on,--mouth-frames-per-shape", &args.frames_per_shape, 1, INT32_MAX,
                 "frames each mouth drawing is held (grid frames with a film grid; default 3)");
  AddNumber(cmd, "--mouth-mid-ratio", &args.mouth_mid_ratio, OpenInterval(0, 1),
            "r of the half-open mouth, M_mid = M_min + r (M_max - M_min) (default 0.5)");
  AddNumber(cmd, "--mouth-min", &args.mouth_min, {},
            "the closed mouth level M_min (default: the curve's minimum)");
  AddNumber(cmd, "--mouth-max", &args.mouth_max, {},
            "the open mouth level M_max (default: the curve's maximum)");
  AddIntervals(cmd, "--speech,--mouth-speech", &args.speech,
               "speech intervals in frames, BEGIN-END with END one past the last (default: "
               "detected where the mouth moves)");
  // eyes
  AddStringList(cmd, "--eyes,--eyes-ids", &args.eye_ids,
                "eye-open curve ids (default ParamEyeLOpen,ParamEyeROpen)");
  AddNumber(cmd, "--eyes-mid-ratio", &args.eyes_mid_ratio, OpenInterval(0, 1),
            "r of the half-open eye, E_mid = E_min + r (E_max - E_min) (default 0.5)");
  AddNumber(cmd, "--eyes-threshold", &args.eyes_threshold, OpenInterval(0, 0.5),
            "delta: closed at or below E_min + delta of the range, open within delta of the "
            "open level (default 0.1)");
  AddNumber(cmd, "--eyes-min", &args.eyes_min, {},
            "the closed eye level E_min (default: the curves' minimum)");
  AddNumber(cmd, "--eyes-max", &args.eyes_max, {},
            "the open eye level E_max, every blink's open drawing (default: each blink "
            "opens to the input's own level)");
  AddBool(cmd, "--eyes-linked", &args.eyes_linked,
          "one blink timing for all eye curves (default true)");
  cmd->add_flag("--unlinked-eyes", args.unlinked_eyes, "same as --eyes-linked false");
  // eyes.auto_blink
  AddNumber(cmd, "--auto-blink,--auto-blink-mean-interval-s", &args.auto_blink_mean_s, Above(0),
            "insert blinks about every MEAN_S seconds where the eyes do not blink (default 4 "
            "when auto-blinks are on)")
      ->type_name("MEAN_S");
  AddBool(cmd, "--auto-blink-enabled", &args.auto_blink_enabled,
          "insert automatic blinks (default: on when any --auto-blink* flag is given)");
  AddNumber(cmd, "--auto-blink-spread-s", &args.auto_blink_spread_s, AtLeast(0),
            "intervals uniform in mean +- spread seconds, spread < mean (default min(1, mean/4))")
      ->type_name("SECONDS");
  AddWholeNumber(cmd, "--auto-blink-hold", &args.auto_blink_hold, 1, 3,
                 "frames an automatic blink stays closed, then half-open (default 2)");
  AddIntervals(cmd, "--auto-blink-keep", &args.auto_blink_keep,
               "frames automatic blinks must not touch, BEGIN-END,...");
  // voice
  cmd->add_option("--audio", args.audio,
                  "a voice recording (WAV, FLAC, Ogg Vorbis/Opus, MP3): speech and mouth "
                  "drawings from it; without IN, a new motion at --fps")
      ->type_name("FILE");
  cmd->add_option("--rhubarb", args.rhubarb,
                  "Rhubarb Lip Sync mouth cues (its JSON or TSV) in place of --audio")
      ->type_name("FILE");
  cmd->add_option("--motion", args.motion, "the motion the voice's mouth goes into (same as IN)")
      ->type_name("FILE");
  cmd->add_option("--cues", args.cues,
                  "with --audio/--rhubarb: the mouth as Rhubarb cues, OUT.tsv as TSV, else JSON")
      ->type_name("OUT");
  AddVoiceSettingsFlags(cmd, args,
                        {"the room noise's loudness, dBFS <= 0 (default: the "
                         "--voice-settings-noise-percentile)",
                         "percentile of the frames' loudness taken as the noise floor (default 10)",
                         "and lasts while frames stay this many dB above it (default: a fifth of "
                         "the recording's range, 2 to the start)"});
  AddNumber(cmd, "--voice-motion-fps", &args.voice_motion_fps, Above(0),
            "frames per second of the motion written for a voice alone (default --fps, 30)");
  AddChoice(cmd, "--voice-output", &args.voice_output, {"motion3", "csv"},
            "the file of a voice alone (default: from -o's name)");
  AddWholeNumber(cmd, "--report-audio-max-bytes", &args.report_audio_max_bytes, 0, INT32_MAX,
                 "with --audio and --report: a recording up to this size is embedded in the "
                 "page, a larger one linked by its path (default 16777216)")
      ->type_name("BYTES");
  // Spine skeleton IN (client/spine_lip_blink.h; LipBlinkRequest.spine, whose field paths
  // the --spine-* aliases spell)
  cmd->add_option("--animation,--spine-animation", args.spine_animation,
                  "Spine IN: the animation to write the mouth and eyes into (added if missing)")
      ->type_name("NAME");
  cmd->add_option("--mouth-slot,--spine-mouth-slot", args.mouth_slot,
                  "Spine IN: the mouth slot, keyed with its three attachments")
      ->type_name("SLOT");
  AddStringList(cmd, "--mouth-attachments,--spine-mouth-attachments", &args.mouth_attachments,
                "Spine IN: the mouth slot's CLOSED,MID,OPEN attachments (default "
                "<slot>_closed,<slot>_mid,<slot>_open)");
  AddStringList(cmd, "--eye-slot,--eye-slots,--spine-eye-slots", &args.eye_slots,
                "Spine IN: eye slots, keyed with their three attachments");
  AddStringList(cmd, "--eye-attachments,--spine-eye-attachments", &args.eye_attachments,
                "Spine IN: the eye slots' OPEN,HALF,CLOSED attachments (default "
                "<slot>_open,<slot>_half,<slot>_closed)");
  AddSeed(cmd, "--seed", &args.seed,
          "seed of the random mouth shapes and auto-blinks, 0 .. 2^64-1 (default 0x6b6f6d61)");
  AddCurveFileFlags(cmd, args, "mouth and blink holds are");
  return cmd;
}

void AddVoiceSettingsFlags(CLI::App* cmd, LipBlinkArgs& args, const VoiceSettingsHelp& help) {
  const auto db = [cmd](const char* name, std::optional<double>* out, NumberBounds bounds,
                        const char* text) { AddNumber(cmd, name, out, bounds, text)->type_name("DB"); };
  db("--voice-settings-noise-floor-dbfs", &args.noise_floor_dbfs, {}, help.noise_floor);
  AddNumber(cmd, "--voice-settings-noise-percentile", &args.noise_percentile, OpenInterval(0, 100),
            help.noise_percentile);
  db("--voice-settings-start-above-floor-db", &args.start_above_floor_db, Above(0),
     "speech starts at a frame this many dB above the floor (default 9)");
  db("--voice-settings-stay-above-floor-db", &args.stay_above_floor_db, Above(0),
     help.stay_above_floor);
  db("--voice-settings-min-speech-dbfs", &args.min_speech_dbfs, {},
     "neither threshold below this, dBFS (default -55)");
  AddWholeNumber(cmd, "--voice-settings-bridge-gap-frames", &args.bridge_gap_frames, 0, INT32_MAX,
                 "gaps of at most this many frames inside speech are bridged (default 3)");
  AddWholeNumber(cmd, "--voice-settings-faint-gap-frames", &args.faint_gap_frames, 0, INT32_MAX,
                 "longer gaps up to this many frames are bridged when no frame of theirs falls "
                 "to the pause level (default 4)");
  db("--voice-settings-pause-above-floor-db", &args.pause_above_floor_db, AtLeast(0),
     "a frame at most this many dB above the floor is a pause, never bridged (default 1)");
  AddWholeNumber(cmd, "--voice-settings-min-speech-frames", &args.min_speech_frames, 1, INT32_MAX,
                 "shorter speech is dropped (default 2)");
  db("--voice-settings-open-below-peak-db", &args.open_below_peak_db, Above(0),
     "follow: open within this many dB of the speech's loud level (default 6)");
  db("--voice-settings-closed-below-peak-db", &args.closed_below_peak_db, Above(0),
     "follow: closed more than this many dB below it (default 15)");
  db("--voice-settings-hysteresis-db", &args.hysteresis_db, AtLeast(0),
     "follow: a frame changes drawing only past a boundary by half of this (default 3)");
  cmd->add_flag("--voice-settings-any-sound", args.any_sound,
                "speech by loudness alone: any loud sound opens the mouth (singing, a "
                "synthesised voice); default: only what sounds like a voice, not music or noise");
}

}  // namespace koma::client
