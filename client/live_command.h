// `koma live`: a voice to the LiveLipBlink stream as it is heard, the decided frames out as
// they arrive (docs/live.md). One thread sends the setup, then 10 ms audio chunks paced to
// real time (client/live_audio_source.h), then WritesDone; the calling thread reads the frames
// and hands each to the sinks (client/live_sink.h: --json lines, --record motion3.json, the
// human lines, the avatar links). Ctrl-C ends the audio: the last frames are still read and
// the sinks closed.
#ifndef KOMA_CLIENT_LIVE_COMMAND_H_
#define KOMA_CLIENT_LIVE_COMMAND_H_

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "client/avatar_sink_flags.h"
#include "client/call_flags.h"
#include "client/lip_blink_command.h"
#include "client/live_audio_source.h"
#include "client/live_sink.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

struct LiveArgs : CallFlags {
  LiveArgs() { deadline_seconds = 0.0; }  // --deadline: none unless given (0)
  // The audio.
  std::string input;                // --input FILE: a recording played at real time
  std::string device;               // --device NAME: the ALSA capture device; empty: "default"
  std::optional<double> seconds;    // --seconds S: stop after S seconds of audio
  double speed = 1.0;               // --speed X: --input at X times real time; 0 at once
  // The stream's settings.
  std::optional<int> lookahead;  // --lookahead 0..3 (the server checks; unset: its 2)
  // The mouth, eye, voice flags lipblink shares (mode, on, mouth-mid-ratio/min/max,
  // eyes-mid-ratio/min/max, auto-blink*, voice-settings-*, seed, timing-fps), kept in
  // lipblink's struct so BuildLipBlinkRequest builds them.
  LipBlinkArgs settings;
  // The outputs (besides --json, one line per frame on stdout).
  std::string record;  // --record OUT.motion3.json
  // The avatar links (--vmc, --vts; client/avatar_sink_flags.h), made into sinks in
  // client/live_sinks.cc.
  AvatarSinkFlags avatar;
};

// Where the human lines go: standard error when standard output carries --json or --record -.
inline std::FILE* LiveTextStream(const LiveArgs& args) {
  return args.json || args.record == "-" ? stderr : stdout;
}

// Registers `koma live` and its flags on `app`.
CLI::App* AddLiveCommand(CLI::App& app, LiveArgs& args);

// Usage errors: --speed below 0, --seconds not above 0, --device with --input, --record -.
absl::Status CheckLiveFlags(const LiveArgs& args);

// The stream's first message: `format` and the settings of `args`.
v1::LiveLipBlinkSetup BuildLiveSetup(const LiveArgs& args, const LiveAudioFormat& format);

// Exit code: 0 ok (also after Ctrl-C), 1 failure (the server's status, a file, the device, a
// sink), 2 usage error. Messages on stderr.
int RunLive(const LiveArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_LIVE_COMMAND_H_
