// `koma curves IN -o OUT ...`: motion3.json (or per-frame CSV) in, RetimeCurves, the curves
// drawn on twos/threes with tame/tsume out.
#ifndef KOMA_CLIENT_CURVES_COMMAND_H_
#define KOMA_CLIENT_CURVES_COMMAND_H_

#include <optional>
#include <string>
#include <vector>

namespace koma::client {

struct CurvesArgs {
  std::string input;                      // .motion3.json, or .csv (frame,<id>,... per frame)
  std::string output;                     // .motion3.json (needs a motion3 input) or .csv
  std::string timing;                     // drawing sheet CSV to write; empty: none
  std::string report;                     // --report: HTML report to write; empty: none
  std::optional<int> frames_per_drawing;  // --on; unset: server default (3)
  std::vector<int> keys;                  // --keys; empty: keyframe times
  std::optional<double> tame;             // --tame; unset: 1
  std::optional<double> tsume;            // --tsume; unset: 1
  std::vector<std::string> curve_on;      // --curve-on ID=N, repeatable
  double csv_fps = 30.0;                  // --fps, frames per second of a CSV input
  std::optional<double> timing_fps;       // --timing-fps: the film grid; unset: server's 24
  std::string server;
  double deadline_seconds = 60.0;
};

// Exit code: 0 ok, 1 failure (message on stderr), 2 a malformed --curve-on or an output the
// input cannot make. The summary goes to stdout.
int RunCurves(const CurvesArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CURVES_COMMAND_H_
