// `koma lipblink IN -o OUT ...`: mouth and eye curves in (motion3.json or per-frame CSV),
// LipBlink, three-drawing mouths and anime blinks out; other curves untouched.
#ifndef KOMA_CLIENT_LIP_BLINK_COMMAND_H_
#define KOMA_CLIENT_LIP_BLINK_COMMAND_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace koma::client {

struct LipBlinkArgs {
  std::string input;                        // .motion3.json or .csv
  std::string output;                       // .motion3.json (needs a motion3 input) or .csv
  std::string report;                       // --report: HTML report to write; empty: none
  std::vector<std::string> mouth_ids;       // --mouth; empty: ParamMouthOpenY
  std::vector<std::string> eye_ids;         // --eyes; empty: ParamEyeLOpen, ParamEyeROpen
  std::string mode = "random";              // --mode random|follow
  std::optional<uint64_t> seed;             // --seed; unset: the server's default
  std::optional<double> auto_blink_mean_s;  // --auto-blink MEAN_S
  std::optional<int> frames_per_shape;      // --on
  bool unlinked_eyes = false;               // --unlinked-eyes
  double csv_fps = 30.0;                    // --fps of a CSV input
  std::optional<double> timing_fps;         // --timing-fps: the film grid; unset: server's 24
  std::string server;
  double deadline_seconds = 60.0;
};

// Exit code: 0 ok, 1 failure (message on stderr), 2 an output the input cannot make.
int RunLipBlink(const LipBlinkArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_LIP_BLINK_COMMAND_H_
