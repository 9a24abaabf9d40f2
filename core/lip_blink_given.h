// LipBlink with a given timing (docs/semantics.md, "A given timing"): mouth holds and blinks
// the caller gives, painted as computed ones are (same levels, same blink paint), so a computed
// answer's holds and blinks given back give the same curves.
#ifndef KOMA_CORE_LIP_BLINK_GIVEN_H_
#define KOMA_CORE_LIP_BLINK_GIVEN_H_

#include <vector>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "absl/types/span.h"
#include "core/lip_blink.h"

namespace koma {

// Holds in time order, disjoint, each length >= 1 within [0, frame_count), shape a MouthShape.
// INVALID_ARGUMENT naming `path`[i] and the hold ("given_timing.mouths[0].holds[3]: begins at
// 12, inside holds[2] (10 + 4 frames)").
absl::Status ValidateGivenHolds(const std::vector<MouthHold>& holds, int frame_count,
                                absl::string_view path);

// Blinks in time order: 0 <= closing_begin <= closed_begin <= closed_end < frame_count, hold
// 1..3, 0 <= open_span <= frame_count, each closing_begin after the previous blink's closed_end (so every
// blink's paint is a forward run of frames). INVALID_ARGUMENT naming `path`[i].
absl::Status ValidateGivenBlinks(const std::vector<Blink>& blinks, int frame_count,
                                 absl::string_view path);

// The mouth `input` (one value per frame) with the given holds (ValidateGivenHolds OK): levels
// as ConvertMouth sets them (options.min / max, else the input's extent), each hold at its
// shape's level, the input elsewhere; speech = the holds' union (touching holds join).
MouthResult PaintGivenMouth(absl::Span<const double> input, const MouthOptions& options,
                            const std::vector<MouthHold>& holds);

// The eye curves with the given blinks, per curve (each ValidateGivenBlinks OK), painted as
// ConvertEyes paints its blinks: levels per curve as it sets them, open levels read around each
// blink (a blink marked automatic: where it ends).
EyeResult PaintGivenEyes(const std::vector<absl::Span<const double>>& eyes,
                         const EyeOptions& options, const std::vector<std::vector<Blink>>& blinks);

}  // namespace koma

#endif  // KOMA_CORE_LIP_BLINK_GIVEN_H_
