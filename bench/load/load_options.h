// Command-line options of koma_load, the ghz-like load generator for the koma service.
#ifndef KOMA_BENCH_LOAD_LOAD_OPTIONS_H_
#define KOMA_BENCH_LOAD_LOAD_OPTIONS_H_

#include <cstdint>
#include <optional>
#include <string>

namespace koma::load {

struct LoadOptions {
  std::string rpc;                         // "skeletal", "curves" or "lipblink"
  std::string target = "127.0.0.1:50051";  // host:port[,host:port...] or dns:///name:port
  // The request: from a file (.bvh for skeletal; .motion3.json or .csv for curves and
  // lipblink), or synthesised at the size below.
  std::string input;
  int frames = 129;  // synthetic frames
  int joints = 31;   // synthetic skeleton size
  int curves = 60;   // synthetic curve count (curves; lipblink adds 3 mouth/eye curves)
  std::string form = "channels";  // skeletal synthesis: "channels" (BVH, FK on the server)
                                  // or "positions" (world positions)
  uint64_t seed = 1;              // SplitMix64 seed of the synthetic data
  // skeletal: the request's max_hold (naming a count asks for the paper's algorithm, the same
  // work on servers from before the anime defaults); unset: the server's defaults.
  std::optional<int> max_hold;
  double csv_fps = 30.0;          // frames per second of a .csv input
  // Load shape.
  int concurrency = 1;     // closed loop: outstanding calls
  int channels = 1;        // gRPC channels (connections) the calls are spread over
  double rate = 0.0;       // open loop: calls per second on a fixed schedule; 0 = closed loop
  int max_inflight = 256;  // open loop: most calls outstanding before sends wait
  // Bounds: the run ends at whichever comes first.
  std::optional<double> duration_s;  // measured seconds after the warmup
  std::optional<int64_t> count;      // measured calls after the warmup
  double max_duration_s = 60.0;      // hard cap on warmup + measured time, seconds
  double warmup_s = 0.0;             // seconds whose calls are not in the statistics
  double deadline_s = 20.0;          // per call, seconds
  // Output.
  std::string json_path;       // also write the report as JSON here
  bool fail_on_error = false;  // exit 1 when any call failed
  bool quiet = false;          // no text table on stdout
};

// Parses argv into `options`. Returns -1 to go on, else the exit code to return at once
// (0 after --help, 2 after a usage error, which it prints to stderr with the usage).
int ParseLoadOptions(int argc, char** argv, LoadOptions* options);

}  // namespace koma::load

#endif  // KOMA_BENCH_LOAD_LOAD_OPTIONS_H_
