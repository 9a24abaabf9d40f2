// What `koma skeletal` tells about a retiming: the human summary and the --json summary
// (schema: docs/summary.schema.json, "skeletal").
#ifndef KOMA_CLIENT_SKELETAL_SUMMARY_H_
#define KOMA_CLIENT_SKELETAL_SUMMARY_H_

#include <nlohmann/json.hpp>
#include <string>

#include "client/skeletal_command.h"
#include "core/skeleton.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// Lines ending in "\n": frames in and out, omissions, duplicates, holds (as frame ranges),
// the film grid, the files written.
std::string SkeletalSummaryText(const SkeletalArgs& args, const SkeletalClip& clip,
                                const v1::RetimeSkeletalResponse& response);

// The same as one JSON object (without the common koma_version/command/status fields).
nlohmann::json SkeletalSummaryJson(const SkeletalArgs& args, const SkeletalClip& clip,
                                   const v1::RetimeSkeletalResponse& response);

}  // namespace koma::client

#endif  // KOMA_CLIENT_SKELETAL_SUMMARY_H_
