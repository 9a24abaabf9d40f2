// `koma skeletal IN.bvh -o OUT.bvh ...`: BVH in, RetimeSkeletal, BVH (+ timing sheet) out.
#ifndef KOMA_CLIENT_SKELETAL_COMMAND_H_
#define KOMA_CLIENT_SKELETAL_COMMAND_H_

#include <optional>
#include <string>

namespace koma::client {

struct SkeletalArgs {
  std::string input;                 // BVH file to read
  std::string output;                // BVH file to write
  std::string timing;                // timing sheet CSV to write; empty: none
  std::string report;                // --report: HTML report to write; empty: none
  std::optional<int> omissions;      // --omit; unset: server default (4)
  std::optional<int> holds;          // --hold; unset: server default (N / 3)
  std::optional<int> max_hold;       // --max-hold; unset: server default (3)
  bool keep_length = true;           // --no-keep-length turns it off
  bool hold_first = false;           // --hold-first: holds before omissions
  bool root_relative = false;        // --root-relative
  std::optional<double> timing_fps;  // --timing-fps: the film grid; unset: server default (24)
  bool output_at_timing_rate = false;  // --output-rate timing: write the BVH at the grid rate
  std::string server;                // host:port
  double deadline_seconds = 60.0;    // --deadline
};

// Exit code: 0 ok, 1 failure (message on stderr). The summary goes to stdout.
int RunSkeletal(const SkeletalArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_SKELETAL_COMMAND_H_
