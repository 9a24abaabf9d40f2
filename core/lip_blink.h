// LipBlink (Miyamune et al. section 3.2): three-drawing mouth flaps and anime blinks.
// See docs/semantics.md, "LipBlink". Frames are integer indices; an interval is
// half-open [begin, end).
#ifndef KOMA_CORE_LIP_BLINK_H_
#define KOMA_CORE_LIP_BLINK_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "absl/types/span.h"

namespace koma {

struct FrameInterval {
  int begin = 0;  // first frame
  int end = 0;    // one past the last frame
  friend bool operator==(const FrameInterval& a, const FrameInterval& b) {
    return a.begin == b.begin && a.end == b.end;
  }
};

// The three mouth drawings, ordered by how open they are.
enum class MouthShape : uint8_t { kClosed = 0, kMid = 1, kOpen = 2 };

enum class MouthMode : uint8_t {
  kRandom,  // the paper: each hold picks uniformly between the two shapes allowed
  kFollow,  // beyond the paper: the allowed shape nearest the mean of the input over the hold
};

struct MouthOptions {
  int frames_per_shape = 3;   // n: every hold lasts n frames (the last of an interval may be shorter)
  MouthMode mode = MouthMode::kRandom;
  double mid_ratio = 0.5;     // r in (0, 1): M_mid = M_min + r (M_max - M_min)
  std::optional<double> min;  // M_min (closed); default: the curve's minimum
  std::optional<double> max;  // M_max (open); default: the curve's maximum
  // Speech intervals, sorted, disjoint, within the clip. Empty with detect_speech: detected (the
  // frames where the curve changes by more than 1e-6 of its range, gaps shorter than n merged).
  std::vector<FrameInterval> speech;
  // False when the caller gave speech intervals: `speech` is then used even when it is empty
  // (on a film grid, given intervals shorter than a grid frame vanish), and the mouth keeps its
  // input values. True (the default): an empty `speech` is detected.
  bool detect_speech = true;
};

struct MouthHold {
  int begin = 0;   // first frame
  int length = 0;  // frames
  MouthShape shape = MouthShape::kClosed;
};

struct MouthResult {
  std::vector<double> values;          // per frame: the shape's level inside speech, else input
  std::vector<FrameInterval> speech;   // the intervals used (given or detected)
  std::vector<MouthHold> holds;        // in time order
  double closed = 0.0, mid = 0.0, open = 0.0;  // the three levels used
};

// INVALID_ARGUMENT naming the option ("frames_per_shape: 0 must be >= 1",
// "speech[2]: [40, 38) is empty or reversed", ...). `frame_count` is the curve length.
absl::Status ValidateMouthOptions(const MouthOptions& options, int frame_count);

// The mouth curve `input` (one value per frame) as three drawings. Holds start at each
// interval's first frame; the shape before an interval's first hold counts as closed, so the
// first hold is mid or open, and no hold repeats the previous one. RANDOM draws one bit per
// hold from SplitMix64(seed); FOLLOW uses no randomness (ties go to the more closed shape).
MouthResult ConvertMouth(absl::Span<const double> input, const MouthOptions& options,
                         uint64_t seed);

struct AutoBlinkOptions {
  bool enabled = false;
  double mean_interval_s = 4.0;  // seconds between blinks on average (CubismEyeBlink: 4 s)
  double spread_s = 1.0;         // intervals are uniform in [mean - spread, mean + spread]
  int hold = 2;                  // frames closed, then frames half-open (1..3)
  // Frames auto-blinks must not touch (beyond the detected blinks, which they never touch).
  std::vector<FrameInterval> keep;
};

struct EyeOptions {
  double mid_ratio = 0.5;      // E_mid = E_min + r (E_max - E_min), r in (0, 1)
  double threshold = 0.1;      // delta: closed <= E_min + delta*range, open >= E_max - delta*range
  std::optional<double> min;   // E_min; default the clip's minimum (0 if the curves are flat)
  // E_max: given, every blink's open drawing (the paper); default the clip's maximum, which
  // then only scales delta, and each blink opens to the input's own level (BlinkLevels).
  std::optional<double> max;
  bool linked = true;          // one blink timing for all eye curves
  AutoBlinkOptions auto_blink;
  double fps = 30.0;           // frames per second, for the auto-blink intervals
};

struct Blink {
  int closing_begin = 0;  // first frame of the closing phase (== closed_begin when none)
  int closed_begin = 0;   // C_start
  int closed_end = 0;     // C_end (inclusive)
  int open_span = 0;      // O_span, frames
  int hold = 1;           // k from O_total (paper Eq. 7): 1, 2 or 3
  bool automatic = false; // inserted by auto-blink
};

// The open drawing's level either side of one blink, on one eye curve (docs/semantics.md,
// "LipBlink", "Open levels"): E_max when `max` is given; else the input's own level.
struct BlinkLevels {
  double before = 0.0;  // the closing phase: the level the eye closes from
  double after = 0.0;   // where it reopens to: the open frames after, the half drawing's top
};

struct EyeResult {
  std::vector<std::vector<double>> values;  // per eye curve, per frame
  // Per eye curve (linked: the same list for every curve, computed once on their average).
  std::vector<std::vector<Blink>> blinks;
  // Per eye curve, per blink (parallel to `blinks`): the open levels painted.
  std::vector<std::vector<BlinkLevels>> levels;
  // Per eye curve: E_min (the closed drawing), E_max (given, or the curve's max: the scale of
  // delta) and E_mid = E_min + r (E_max - E_min). The open and half drawings of a blink are
  // E_max and E_mid only when `max` is given; else they follow `levels`.
  std::vector<double> closed, mid, open;
};

absl::Status ValidateEyeOptions(const EyeOptions& options, int frame_count);

// Eye curves (each one value per frame, same length) with anime blinks: the closing phase
// snaps to open, closed from C_start through max(C_end, C_start + k - 1), then half-open for k
// frames, then open; never past the clip or into the next blink. Open is the level the eye
// closes from (closing phase) and reopens to (after), half between closed and the latter.
// Auto-blinks, when enabled, are drawn from SplitMix64(seed ^ kAutoBlinkStream) so turning them on
// does not change the mouth's draws.
EyeResult ConvertEyes(const std::vector<absl::Span<const double>>& eyes,
                      const EyeOptions& options, uint64_t seed);

// The three drawings per frame, for writers that key drawings rather than levels (a Spine
// slot's attachments): a mouth shows closed outside its holds and each hold's shape inside; an
// eye open outside its blinks shows each blink as ConvertEyes paints it (closing phase open,
// closed through max(C_end, C_start + k - 1), k frames half-open = kMid, then open, cut at
// the next blink's closing or the clip's end). Holds and blinks past frame_count are cut.
std::vector<MouthShape> MouthDrawings(const std::vector<MouthHold>& holds, int frame_count);
std::vector<MouthShape> BlinkDrawings(const std::vector<Blink>& blinks, int frame_count);

}  // namespace koma

#endif  // KOMA_CORE_LIP_BLINK_H_
