// Pieces shared by RetimeNaive and RetimeFast (not part of the public API).
#ifndef KOMA_CORE_RETIME_INTERNAL_H_
#define KOMA_CORE_RETIME_INTERNAL_H_

#include <array>
#include <cstdint>
#include <vector>

#include "core/retime.h"

namespace koma::retime_internal {

// The two steps of RetimeSkeletal, and "not gone" for a source frame still shown.
enum class Step : uint8_t {
  kNone,
  kOmit,  // step A: delete (+ duplicate)
  kHold,  // step B: hold
};

// The steps in the order `order` runs them.
std::array<Step, 2> StepsInOrder(StepOrder order);

// Fills map.deleted (gone during kOmit) and map.hidden (gone during kHold) in ascending
// source order from `gone_in`, which has one entry per source frame.
void FillGoneFrames(const std::vector<Step>& gone_in, TimingMap& map);

// RetimeFast with the clip length from which it reads step B's unlink distances from tables
// (kTableMinFrames, in core/retime_fast.cc), so tests can take that path on clips small
// enough for RetimeNaive.
// `known_ssd`: as RetimeFastWithInputSsd's `ssd` (nullptr: computed).
TimingMap RetimeFastWithTablesFrom(const FrameDistance& distance, const RetimeOptions& options,
                                   std::vector<double>* input_ssd, int table_min_frames,
                                   std::vector<double>* known_ssd = nullptr);

}  // namespace koma::retime_internal

#endif  // KOMA_CORE_RETIME_INTERNAL_H_
