// `koma skeletal IN.fbx -o OUT.fbx` (docs/usage.md, "FBX"): the file travels whole in
// RetimeSkeletalRequest.fbx, the server evaluates the take and answers the same file with the
// take retimed; the summary, --json, --timing, --xdts and --report read the response.
#ifndef KOMA_CLIENT_SKELETAL_FBX_H_
#define KOMA_CLIENT_SKELETAL_FBX_H_

#include <string>

#include "client/skeletal_command.h"

namespace koma::client {

bool IsFbxInput(const std::string& path, const std::string& bytes);

// The request: the file in `fbx`, --take in fbx_take, the options of every skeletal request.
absl::StatusOr<v1::RetimeSkeletalRequest> BuildFbxRequest(const SkeletalArgs& args,
                                                          std::string bytes);

// -o (the server's file), --timing and --xdts from the response.
absl::Status WriteFbxOutputs(const SkeletalArgs& args, const v1::RetimeSkeletalResponse& response);

// --report: the take's world positions evaluated here, as the server evaluated them.
absl::Status WriteFbxReport(const std::string& path, const v1::RetimeSkeletalRequest& request,
                            const v1::RetimeSkeletalResponse& response, const std::string& input);

int RunSkeletalFbx(const SkeletalArgs& args, std::string bytes);

}  // namespace koma::client

#endif  // KOMA_CLIENT_SKELETAL_FBX_H_
