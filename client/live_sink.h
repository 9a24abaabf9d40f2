// Where `koma live` sends each decided frame of a LiveLipBlink stream (client/live_command.h):
// a list of sinks, each given every frame in order. The --json line writer and the --record
// motion3.json recorder are sinks; so are the avatar links (--vmc, --vts). A sink is made
// before the stream starts, given the setup once (Start), every frame (Frame), then Close
// once, on the thread that reads the stream, so a sink needs no lock of its own.
#ifndef KOMA_CLIENT_LIVE_SINK_H_
#define KOMA_CLIENT_LIVE_SINK_H_

#include "absl/status/status.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// When a frame arrived, on the client's steady clock.
struct LiveFrameTiming {
  // Milliseconds from sending (for the microphone: capturing) the audio chunk that completes
  // the frame's audio to receiving the frame: the server's lookahead (frame.late_ms) plus the
  // chunk, the transport and the analysis. After the audio ended (end of --input, --seconds,
  // Ctrl-C) the chunk is the last one sent.
  double wall_late_ms = 0.0;
  // Seconds from the stream's start (the setup sent) to receiving the frame.
  double wall_s = 0.0;
};

class LiveSink {
 public:
  virtual ~LiveSink() = default;

  // Once, before the first frame: the setup the stream was opened with (the levels, the
  // film grid; unset fields mean the server's defaults, see LiveLipBlinkSetup). An error ends
  // the command before any audio is sent.
  virtual absl::Status Start(const v1::LiveLipBlinkSetup& setup) {
    (void)setup;
    return absl::OkStatus();
  }

  // Each decided frame, in order from grid_frame 0, as soon as it arrives. Must not block for
  // long: the next frames wait (a network sink sends without waiting for an answer). An error
  // ends the stream (WritesDone) and the command exits 1 with the message; a sink that can
  // lose a frame without harm (a UDP packet) warns on stderr itself and returns OK. CANCELLED
  // ends the stream as Ctrl-C does, exit 0 and no message (the reader of --json's pipe left).
  virtual absl::Status Frame(const v1::LiveLipBlinkFrame& frame,
                             const LiveFrameTiming& timing) = 0;

  // Once, after the last frame (also after an error or Ctrl-C): flush, write files, close
  // sockets. An error makes the command exit 1 with the message.
  virtual absl::Status Close() { return absl::OkStatus(); }
};

}  // namespace koma::client

#endif  // KOMA_CLIENT_LIVE_SINK_H_
