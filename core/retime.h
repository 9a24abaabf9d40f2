// RetimeSkeletal (Kitamura et al.): inbetween omission (nakanashi) and holds (koma-dori) on a
// sequence of poses. See docs/semantics.md, "RetimeSkeletal".
//
// Two implementations with identical results:
//  - RetimeNaive follows the steps literally, rescanning the working sequence each step:
//    O((omissions + holds) * N * J). It is the reference for tests.
//  - RetimeFast keeps the candidates, keyed by (SSD, position), in 4-ary heaps with lazy
//    invalidation and (for holds) lazily sorted SSD buckets, over a linked list of runs (all
//    output frames showing one source frame): O(N*J + (omissions + holds) * (J + log N)).
//    The server uses it; core/retime_fast.cc explains why it gives the same answers.
#ifndef KOMA_CORE_RETIME_H_
#define KOMA_CORE_RETIME_H_

#include <cstdint>
#include <vector>

#include "absl/status/status.h"
#include "core/distance.h"

namespace koma {

enum class FrameKind : uint8_t {
  kOriginal,   // the source frame's own slot of the initial sequence
  kDuplicate,  // a copy inserted by the duplicate half of step A (keep_length)
  kHeld,       // a slot overwritten with its predecessor by step B
};

enum class StepOrder : uint8_t {
  kOmitThenHold,  // the paper's order (section 3.4): A then B
  kHoldThenOmit,
};

struct RetimeOptions {
  int omissions = 4;        // Nio: delete steps to run (each may be followed by a duplicate)
  int holds = 0;            // Nhf: hold steps to run; callers default it to frame_count / 3
  int max_hold = 3;         // longest run of one drawing the algorithm may create, in frames
  bool keep_length = true;  // re-insert a duplicate after each delete
  StepOrder order = StepOrder::kOmitThenHold;
  // Step B stops before a hold step once the sequence shows at most this many drawings
  // (distinct source frames); 0: no target, only `holds` bounds step B. Set from a drawing
  // rate (docs/semantics.md, "Drawing rate").
  int max_drawings = 0;
};

// The paper's defaults for a clip of `frame_count` frames: omissions = min(4, N - 3)
// (never negative), holds = N / 3, max_hold = 3, keep_length, omit then hold.
RetimeOptions DefaultRetimeOptions(int frame_count);

// INVALID_ARGUMENT / OUT_OF_RANGE naming the option and value: frame_count >= 2;
// omissions >= 0 and, when positive, < frame_count - 2; holds >= 0; max_hold >= 1;
// max_drawings >= 0.
absl::Status ValidateRetimeOptions(const RetimeOptions& options, int frame_count);

struct TimingMap {
  // Output frame t shows source frame source_frames[t]; kinds[t] says how it got there.
  std::vector<int32_t> source_frames;
  std::vector<FrameKind> kinds;
  // Source frames no longer shown, ascending: `deleted` lost their last output frame in
  // step A, `hidden` in step B.
  std::vector<int32_t> deleted;
  std::vector<int32_t> hidden;
  int omissions_applied = 0;   // deletes done (stops early when nothing moves)
  int duplicates_applied = 0;  // duplicates inserted (keep_length)
  int duplicates_skipped = 0;  // deletes after which no gap could take a duplicate
  int holds_applied = 0;       // holds done (stops early when no candidate remains)
  // What became of the duplicates afterwards (they are kDuplicate in `kinds` only when
  // neither happened): a later delete of step A removed the output frame, or a hold of step B
  // overwrote it (it is then kHeld). duplicates_applied = the kDuplicate frames + both.
  int duplicates_omitted = 0;
  int duplicates_held = 0;

  friend bool operator==(const TimingMap& a, const TimingMap& b);
};

// Both require ValidateRetimeOptions(options, distance.frame_count()) to be OK.
TimingMap RetimeNaive(const FrameDistance& distance, const RetimeOptions& options);
// RetimeFast computes the input's per-frame SSD on the way; given `input_ssd`, it stores it
// there (bit for bit distance.InputSsd()), so a caller that also reports it need not compute
// it again.
TimingMap RetimeFast(const FrameDistance& distance, const RetimeOptions& options,
                     std::vector<double>* input_ssd = nullptr);

// The input's per-frame SSD as RetimeFast computes it: bit for bit distance.InputSsd(), by the
// faster pass for the clip's size.
std::vector<double> RetimeInputSsd(const FrameDistance& distance);
// RetimeFast given that SSD (RetimeInputSsd(distance), which a caller may have needed first:
// the server's cut search): used instead of computed again, and moved to *input_ssd when that
// is not null. Same answer as RetimeFast, bit for bit.
TimingMap RetimeFastWithInputSsd(const FrameDistance& distance, const RetimeOptions& options,
                                 std::vector<double> ssd, std::vector<double>* input_ssd);

}  // namespace koma

#endif  // KOMA_CORE_RETIME_H_
