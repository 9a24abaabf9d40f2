// `koma curves hero.json -o hero_anime.json [--animation walk ...]` on a Spine skeleton: one
// RetimeCurves call per animation (its bone timelines as curves), the retimed timelines written
// back into the skeleton as stepped keys (formats/spine.h).
#ifndef KOMA_CLIENT_SPINE_CURVES_H_
#define KOMA_CLIENT_SPINE_CURVES_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "client/command_output.h"
#include "client/curves_command.h"

namespace koma::client {

// The animations to retime, as indices into input.spine->animations: the --animation names in
// the order given (NOT_FOUND listing the skeleton's animations for an unknown one,
// INVALID_ARGUMENT for one without bone keys), else every animation with bone keys
// (INVALID_ARGUMENT when there is none).
absl::StatusOr<std::vector<int>> SpineAnimationsToRetime(const CurveInput& input,
                                                         const std::vector<std::string>& names);

// `input` with the one animation to retime selected (convert::SelectSpineAnimation), for the
// drivers that make one call per file (`koma batch`): SpineAnimationsToRetime must give exactly
// one, else INVALID_ARGUMENT asking for --animation and naming the candidates.
absl::Status SelectOneSpineAnimation(CurveInput& input, const std::vector<std::string>& names);

// RunCurves for a Spine input (input.spine set). Exit code as RunCurves.
int RunSpineCurves(const CurvesArgs& args, const CurveInput& input, const CommandOutput& out);

}  // namespace koma::client

#endif  // KOMA_CLIENT_SPINE_CURVES_H_
