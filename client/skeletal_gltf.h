// `koma skeletal avatar.glb -o avatar_anime.glb`: a glTF 2.0 file (.glb, .gltf with embedded
// buffers, .vrm, .vrma) sent whole in RetimeSkeletalRequest.gltf; the server answers the same
// file with the retimed animations (docs/usage.md, "glTF and VRM").
#ifndef KOMA_CLIENT_SKELETAL_GLTF_H_
#define KOMA_CLIENT_SKELETAL_GLTF_H_

#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "client/skeletal_command.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// True when `path` names a glTF file (.glb, .gltf, .vrm, .vrma) or its bytes are one.
bool IsGltfInput(const std::string& path, const std::string& bytes);

// The request for the file `bytes` with every flag of `args` applied (--send-file changes
// nothing: a glTF file is always sent whole; --joint-weights takes one weight per joint, by
// position: joint names need the joints, which only the server reads).
absl::StatusOr<v1::RetimeSkeletalRequest> BuildGltfRequest(const SkeletalArgs& args,
                                                           std::string bytes);

// --joint-weights for a file the server reads (glTF, FBX): numbers, one per joint in the order
// of the summary's joints (the names are the server's to read).
absl::Status SetFileJointWeights(const SkeletalArgs& args, v1::RetimeSkeletalRequest* request);

// The flags make sense for a glTF input: -o names a file of the same container (GLB in:
// .glb/.vrm/.vrma; .gltf in: .gltf), the glTF-only flags are not given with a BVH input.
absl::Status CheckGltfFlags(const SkeletalArgs& args, bool input_is_glb);

// Writes -o (the server's file) and --timing (the first retimed animation's sheet).
absl::Status WriteGltfOutputs(const SkeletalArgs& args, const v1::RetimeSkeletalResponse& response);

// The summary lines for a glTF answer.
std::string GltfSummaryText(const SkeletalArgs& args, const v1::RetimeSkeletalResponse& response);

// --report for a glTF request: the first retimed animation's joints as stick figures (the file
// in request.gltf is read again to draw them).
absl::Status WriteGltfReport(const std::string& path, const v1::RetimeSkeletalRequest& request,
                             const v1::RetimeSkeletalResponse& response, const std::string& input);

// The whole command for a glTF input whose bytes are read. Exit code as RunSkeletal's.
int RunSkeletalGltf(const SkeletalArgs& args, std::string bytes);

// True when any glTF-only flag is given (--gltf-animations, --gltf-retime-none,
// --gltf-source-fps, --gltf-keys, --gltf-keep-original): refused with a BVH input.
bool HasGltfFlags(const SkeletalArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_SKELETAL_GLTF_H_
