// `koma live`'s flags. The mouth, eye and voice flags are lipblink's names (bound to
// LiveArgs::settings, a LipBlinkArgs), with the live stream's defaults in their help.
#include "client/cli_options.h"
#include "client/command_flags.h"
#include "client/live_command.h"
#include "client/live_sinks.h"

namespace koma::client {

CLI::App* AddLiveCommand(CLI::App& app, LiveArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "live",
      "A live voice (microphone or a recording at real time) to mouth drawings and blinks as "
      "it is heard (the LiveLipBlink stream; docs/live.md)");
  LipBlinkArgs& s = args.settings;
  // the audio
  cmd->add_option("--input", args.input,
                  "a recording (WAV, FLAC, Ogg Vorbis/Opus, MP3) played at real time, its own "
                  "rate and channels (default: the microphone, --device)")
      ->type_name("FILE");
  cmd->add_option("--device", args.device,
                  "ALSA capture device, 48 kHz mono (default \"default\"; `arecord -L` lists "
                  "them; null: silence)")
      ->type_name("NAME");
  AddNumber(cmd, "--seconds", &args.seconds, Above(0),
            "stop after this many seconds of audio (default: the end of --input, or Ctrl-C)")
      ->type_name("S");
  AddNumberWithDefault(cmd, "--speed", &args.speed, AtLeast(0),
                       "play --input at X times real time; 0 = as fast as the stream takes it "
                       "(default 1)")
      ->type_name("X");
  AddWholeNumber(cmd, "--lookahead,--lookahead-frames", &args.lookahead, INT32_MIN, INT32_MAX,
                 "grid frames of audio the server waits for past a frame before deciding it, "
                 "0..3: each adds 41.7 ms of delay and agrees better with `koma lipblink "
                 "--audio` (default 2)")
      ->type_name("N");
  // the mouth (LiveLipBlinkSetup.mouth)
  AddChoice(cmd, "--mode,--mouth-mode", &s.mode, {"random", "follow"},
            "random (the paper: uniform between the half-open and open mouth) or follow the "
            "voice's loudness (default random)");
  AddWholeNumber(cmd, "--on,--mouth-frames-per-shape", &s.frames_per_shape, 1, INT32_MAX,
                 "grid frames each mouth drawing is held (default 3)");
  AddNumber(cmd, "--mouth-mid-ratio", &s.mouth_mid_ratio, OpenInterval(0, 1),
            "r of the half-open mouth, M_mid = M_min + r (M_max - M_min) (default 0.5)");
  AddNumber(cmd, "--mouth-min", &s.mouth_min, {}, "the closed mouth level (default 0)");
  AddNumber(cmd, "--mouth-max", &s.mouth_max, {},
            "the open mouth level (default max(1, --mouth-min + 1))");
  // the eyes (LiveLipBlinkSetup.eyes)
  AddNumber(cmd, "--eyes-mid-ratio", &s.eyes_mid_ratio, OpenInterval(0, 1),
            "r of the half-open eye, E_mid = E_min + r (E_max - E_min) (default 0.5)");
  AddNumber(cmd, "--eyes-min", &s.eyes_min, {}, "the closed eye level (default 0)");
  AddNumber(cmd, "--eyes-max", &s.eyes_max, {}, "the open eye level (default 1)");
  AddNumber(cmd, "--auto-blink,--auto-blink-mean-interval-s", &s.auto_blink_mean_s, Above(0),
            "anime blinks about every MEAN_S seconds (default 4 when auto-blinks are on; "
            "without any --auto-blink* flag the eyes stay open)")
      ->type_name("MEAN_S");
  AddBool(cmd, "--auto-blink-enabled", &s.auto_blink_enabled,
          "blink automatically (default: on when any --auto-blink* flag is given)");
  AddNumber(cmd, "--auto-blink-spread-s", &s.auto_blink_spread_s, AtLeast(0),
            "intervals uniform in mean +- spread seconds, spread < mean (default min(1, mean/4))")
      ->type_name("SECONDS");
  AddWholeNumber(cmd, "--auto-blink-hold", &s.auto_blink_hold, 1, 3,
                 "grid frames a blink stays closed, then half-open (default 2)");
  // the voice analysis (LiveLipBlinkSetup.voice_settings)
  AddVoiceSettingsFlags(cmd, s,
                        {"the room noise's loudness, dBFS <= 0 (default: the "
                         "--voice-settings-noise-percentile of the last 60 s)",
                         "percentile of the last 60 s of frames' loudness taken as the noise "
                         "floor (default 10)",
                         "and lasts while frames stay this many dB above it (default: a fifth of "
                         "the range heard, 2 to the start)"});
  AddSeed(cmd, "--seed", &s.seed,
          "seed of the random mouth shapes and auto-blinks, 0 .. 2^64-1 (default 0x6b6f6d61)");
  AddNumber(cmd, "--timing-fps", &s.timing_fps, {},
            "the film grid the frames are decided on, frames per second, (0, 1000] (default 24)")
      ->type_name("FPS");
  // the outputs
  cmd->add_option("--record", args.record,
                  "write what was streamed as a Live2D motion3.json (ParamMouthOpenY, "
                  "ParamEyeLOpen, ParamEyeROpen on stepped keys at the film grid) when it ends")
      ->type_name("OUT.motion3.json");
  AddLiveSinkFlags(cmd, args);
  // the connection
  cmd->add_option("--server", args.server,
                  "server host:port, or a list a:p,b:p balanced round-robin (default "
                  "$KOMA_SERVER or 127.0.0.1:50051)")
      ->type_name("HOST:PORT")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  AddNumberWithDefault(cmd, "--deadline", &args.deadline_seconds, AtLeast(0),
                       "RPC deadline: the stream fails with DEADLINE_EXCEEDED this many seconds "
                       "after it starts (default 0: none; --seconds ends a session cleanly)")
      ->type_name("SECONDS");
  cmd->add_flag("--json", args.json,
                "one JSON object per frame on stdout, a line each, as it arrives (docs/live.md); "
                "the human lines go to stderr");
  cmd->add_flag("-q,--quiet", args.quiet, "no human lines or summary (errors still go to stderr)");
  return cmd;
}

}  // namespace koma::client
