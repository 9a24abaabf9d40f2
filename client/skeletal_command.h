// `koma skeletal IN.bvh -o OUT.bvh ...`: BVH in, RetimeSkeletal, BVH (+ timing sheet) out.
// The steps are separate functions so other drivers (`koma batch`) run them per file:
//   ReadSkeletalInput -> BuildSkeletalRequest -> (the RPC) -> WriteSkeletalOutputs
//   -> SkeletalSummaryText / SkeletalSummaryJson (client/skeletal_summary.h).
#ifndef KOMA_CLIENT_SKELETAL_COMMAND_H_
#define KOMA_CLIENT_SKELETAL_COMMAND_H_

#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "client/call_flags.h"
#include "core/retime.h"
#include "core/skeleton.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// Flags of `koma skeletal`. Field per request field (see docs/usage.md); unset optionals
// leave the request field unset, so the server's default applies.
struct SkeletalArgs : CallFlags {
  std::string input;                       // BVH file to read; "-": standard input
  std::string output;                      // BVH file to write; "-": standard output
  std::string timing;                      // timing sheet CSV to write; empty: none; "-": stdout
  std::string report;                      // --report: HTML report to write; empty: none
  std::string xdts;                        // --xdts: XDTS exposure sheet to write; empty: none
  std::string timing_from;  // --timing-from: an edited XDTS or --timing CSV to apply; empty: none
  std::optional<int> omissions;            // --omit / --omissions; unset: server default (4)
  std::optional<int> holds;                // --hold / --holds; unset: server default (N / 3)
  std::optional<int> max_hold;             // --max-hold; unset: server default (3)
  bool keep_length = true;                 // --keep-length / --no-keep-length
  bool hold_first = false;                 // --hold-first: holds before omissions
  std::string order;                       // --order omit-then-hold|hold-then-omit; wins over
                                           // --hold-first when given
  std::vector<std::string> joint_weights;  // --joint-weights: W,... per joint, or NAME=W,...
  bool root_relative = false;              // --root-relative
  std::vector<double> camera;              // --camera: 16 numbers, column-major view-projection
  std::optional<bool> return_motion;  // --return-motion; unset: true (false with --timing-only)
  bool send_file = false;             // --send-file: the BVH text in bvh_text, parsed by the server
  bool timing_only = false;           // --timing-only: no motion asked for, only the sheet written
  std::optional<double> timing_fps;   // --timing-fps: the film grid; unset: server default (24)
  bool output_at_timing_rate = false;  // --output-rate timing: write the BVH at the grid rate
  std::optional<double> omissions_per_second;  // --omissions-per-second; not with --omit
  std::optional<double> drawings_per_second;   // --drawings-per-second: 12 twos, 8 threes
  std::optional<double> cut_neighbour_ratio;   // --cut-neighbour-ratio; 0: no cuts
  std::optional<double> cut_median_ratio;      // --cut-median-ratio
  // glTF input (.glb, .gltf, .vrm, .vrma; client/skeletal_gltf.h):
  std::vector<std::string> animations;  // --gltf-animations NAME|INDEX,...; empty: every one
  bool retime_none = false;             // --gltf-retime-none: the file back, nothing retimed
  std::optional<double> source_fps;     // --gltf-source-fps; unset: from the keys (or 30)
  std::string gltf_keys;                // --gltf-keys step|linear; empty: step
  bool keep_original = false;           // --gltf-keep-original: add "<name>.anime" beside each
  // FBX input (.fbx; client/skeletal_fbx.h):
  std::string take;  // --take NAME: the AnimationStack to retime; empty: the file's current
};

// The clip in `path` ("-": standard input). A motion3.json or CSV is refused as such; a
// malformed BVH names the file and line.
absl::StatusOr<SkeletalClip> ReadSkeletalInput(const std::string& path);

// The same, with the file's text (what --send-file sends).
struct SkeletalInput {
  SkeletalClip clip;
  std::string text;
  // Where the file bent a rule and was read anyway ("take.bvh (BVH): line 3075: ...").
  std::vector<std::string> warnings;
};
absl::StatusOr<SkeletalInput> ReadSkeletalFile(const std::string& path);
// The same on text already read from `path` (a glTF file is refused: RunSkeletalGltf's).
absl::StatusOr<SkeletalInput> ParseSkeletalText(const std::string& path, std::string text);

// BuildSkeletalRequest(args, input.clip); with --send-file the request carries input.text in
// bvh_text instead of motion (the server parses it and answers the retimed file in bvh_text).
absl::StatusOr<v1::RetimeSkeletalRequest> BuildSkeletalFileRequest(const SkeletalArgs& args,
                                                                   const SkeletalInput& input);

// The request for `clip` with every flag of `args` applied. INVALID_ARGUMENT naming the flag
// when a flag does not fit the clip (--joint-weights: a count other than the joints', an
// unknown joint name).
absl::StatusOr<v1::RetimeSkeletalRequest> BuildSkeletalRequest(const SkeletalArgs& args,
                                                               const SkeletalClip& clip);

// --timing-from: the sheet's timing into the request for `clip` (client/timing_from.h), its
// warnings appended to `warnings` (nullptr: standard error). Nothing without the flag.
absl::Status SetSkeletalTimingFromArgs(const SkeletalArgs& args, const SkeletalClip& clip,
                                       v1::RetimeSkeletalRequest* request,
                                       std::vector<std::string>* warnings);

// The options every skeletal request takes from the flags, whatever carries the clip (a
// motion, or a glTF or FBX file the server reads): counts, rates, order, grid, cuts, camera,
// what to return. Not the joint weights, which a decoded clip names and a file's do not.
void SetSkeletalOptions(const SkeletalArgs& args, v1::RetimeSkeletalRequest* request);

// Before reading or calling: the flags make sense together (-o given unless --timing-only,
// --timing given with --timing-only, at most one of -o, --timing and --json on standard
// output). INVALID_ARGUMENT naming the flags: a usage error. Whether the outputs can be
// written is CheckWritable's (client/files.h).
absl::Status CheckSkeletalFlags(const SkeletalArgs& args);

// --xdts: the exposure sheet of the response's timing (a file request's too), to args.xdts.
absl::Status WriteSkeletalXdts(const SkeletalArgs& args,
                               const v1::RetimeSkeletalResponse& response);

// Writes -o (unless --timing-only or the response has no motion; the server's bvh_text as is
// when it answered one) and --timing (when given) from `response` to the request built from
// `clip`.
absl::Status WriteSkeletalOutputs(const SkeletalArgs& args, const SkeletalClip& clip,
                                  const v1::RetimeSkeletalResponse& response);

// The whole command. Exit code: 0 ok, 1 failure, 2 usage error (messages on stderr).
int RunSkeletal(const SkeletalArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_SKELETAL_COMMAND_H_
