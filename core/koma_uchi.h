// RetimeCurves (Miyamune et al. section 3.1): koma-uchi (drawings held for n frames) with
// tame/tsume spacing between key poses. See docs/semantics.md, "RetimeCurves".
#ifndef KOMA_CORE_KOMA_UCHI_H_
#define KOMA_CORE_KOMA_UCHI_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "core/curves.h"
#include "core/key_drawings.h"
#include "core/timing_groups.h"

namespace koma {

// Overrides for the segment between key poses G_x and G_{x+1}.
struct SegmentOverride {
  int segment = 0;                        // x, 0-based
  std::optional<int> frames_per_drawing;  // n for this segment (curves without their own n)
  std::optional<double> tame;             // s_a for this segment
  std::optional<double> tsume;            // s_b for this segment
};

// A timing given for one timing group instead of computed (docs/semantics.md, "A given
// timing"): per counted frame (grid frame with a grid, else source frame), all of the clip's,
// the tau of the drawing it shows; equal consecutive taus are one drawing.
struct GivenGroupTiming {
  std::vector<double> taus;
  // True: every drawing shows the curves at its tau, no key drawn; false: the curves' keys are
  // drawn as for a computed timing (core/key_drawings.h).
  bool exact_taus = false;
};

struct KomaUchiOptions {
  // Key poses in frames, strictly increasing, within [0, frame_count - 1]. Empty: every
  // keyframe time of every keyframe curve, rounded to the nearest frame, merged into poses
  // (merge_key_poses). The first and last frame are always key poses (added if missing).
  std::vector<int> key_frames;
  // With key_frames empty: keyframe times closer than n frames (grid frames with a grid) to
  // the pose before them form one key pose at the earliest of them, those closer than n to
  // the clip's end join its last frame, and each segment gets floor(L / n) drawings (at least
  // one), so no drawing is shorter than n but the clip's last frame (docs/semantics.md, "Key
  // poses"). False: every keyframe time is a key pose and segments get ceil(L / n) drawings,
  // as named key poses do.
  bool merge_key_poses = true;
  int frames_per_drawing = 3;  // n: 1 = on ones, 2 = on twos, 3 = on threes
  double tame = 1.0;           // s_a >= 1: gaps grow by s_a per drawing away from G_x
  double tsume = 1.0;          // s_b >= 1: gaps shrink by s_b per drawing toward G_{x+1}
  // Curve id -> its own n (hair on twos, body on threes). Beats segment overrides of n.
  std::map<std::string, int> curve_frames_per_drawing;
  // Segment indices count the key poses used (after snapping to the grid, with one).
  std::vector<SegmentOverride> segment_overrides;
  // The film grid drawings are counted on, frames per second (core/film_grid.h). <= 0, or
  // the set's own fps (within 1e-4): count in source frames. With a grid, n counts grid
  // frames, key poses snap to the nearest grid frame, and each drawing starts at its exact
  // grid time.
  double timing_fps = 0.0;
  // Timing groups (core/timing_groups.h): each matched curve is timed with its group's key
  // poses, n and spacing; curves no group matches (the default group) with the options above.
  std::vector<CurveTimingGroup> groups;
  // Group name (kDefaultTimingGroupName for the default group) -> its given timing. A group
  // given one has that timing alone: its curves' own n (curve_frames_per_drawing) and its key
  // poses do not shape it. The caller checks them (CheckGivenGroupTiming).
  std::map<std::string, GivenGroupTiming> given;
};

// INVALID_ARGUMENT naming the option and value: keys unsorted, duplicate or outside the
// range; n < 1; strengths < 1 or not finite; an override naming an unknown curve or a
// segment out of range, or given twice; timing_fps not finite or over 1000, or a grid on
// which the clip spans fewer than 2 frames (OUT_OF_RANGE).
absl::Status ValidateKomaUchiOptions(const KomaUchiOptions& options, const CurveSet& set);

// A given timing for a clip of `frame_count` frames counted in `counted_frames` frames (its
// grid frames with a grid): exactly counted_frames taus, each finite and within
// [0, frame_count - 1]. INVALID_ARGUMENT naming `field` ("given_timings[0].source_frame[3]: 61.5
// is past the clip's last frame 59").
absl::Status CheckGivenGroupTiming(const GivenGroupTiming& given, int frame_count,
                                   int counted_frames, absl::string_view field);

// The key poses actually used: options.key_frames (or the keyframe times of the curves
// `members` lists, all when null) plus 0 and frame_count - 1, sorted, unique. Before merging.
std::vector<int> KeyPoses(const KomaUchiOptions& options, const CurveSet& set,
                          const std::vector<int>* members = nullptr);

// The key poses on the film grid of options.timing_fps: each snaps to its nearest grid frame
// (within the clip's grid frames); when several snap to one grid frame the first is kept,
// except that the clip's last frame always takes the last grid frame. `source` are the
// surviving key poses in source frames, `grid` their grid frames. Without a grid both are
// KeyPoses().
struct GridKeyPoses {
  std::vector<int> source;
  std::vector<int> grid;
  // With merged key poses (MergesKeyPoses): per key pose, how many keyframe times (distinct
  // frames) it stands for, 1 for a pose no other joined. Empty otherwise.
  std::vector<int> merged;
};
// True when the key poses are the keyframes merged into poses: options.merge_key_poses and no
// key_frames named.
bool MergesKeyPoses(const KomaUchiOptions& options);
GridKeyPoses KeyPosesOnGrid(const KomaUchiOptions& options, const CurveSet& set,
                            const std::vector<int>* members = nullptr);

// The options a timing group's curves are timed with: the group's n, spacing and key poses,
// the request's for what the group leaves unset; no segment overrides (those are the default
// group's).
KomaUchiOptions GroupOptions(const KomaUchiOptions& options, const CurveTimingGroup& group);

// Per group of options.groups, then the default group last: the indices of its curves, in
// the set's order.
std::vector<std::vector<int>> GroupMembers(const KomaUchiOptions& options, const CurveSet& set);

// Hold lengths of one segment of `length` frames at n frames per drawing: ceil(length / n)
// holds, as even as possible, longer ones first (10 at n = 3 -> 3, 3, 2, 2).
std::vector<int> HoldLengths(int length, int frames_per_drawing);

// Hold lengths between merged key poses: max(1, floor(length / n)) holds, as even as possible,
// longer ones first, so none is shorter than n when length >= n (10 at n = 3 -> 4, 3, 3).
std::vector<int> PoseHoldLengths(int length, int frames_per_drawing);

// E_0 .. E_{D-1} of docs/semantics.md, "RetimeCurves": E_0 = 0, strictly increasing, j / D when
// tame = tsume = 1, geometric with ratio tame in the first half and 1 / tsume in the second.
// Powers by repeated multiplication (and one sqrt for an odd D), so the bits are the same on
// every machine.
std::vector<double> Spacing(int drawings, double tame, double tsume);

// One timing: how output frames map to drawings and source times.
struct DrawingTiming {
  int frames_per_drawing = 3;         // the n this timing was made with (default n)
  std::vector<int> drawing_of_frame;  // per output frame: its drawing, 0-based, global
  // Per output frame: tau of its drawing, in source frames. A segment's taus run between its
  // key poses' own times (not the grid frames they snapped to), the clip's last drawing shows
  // its last frame. A curve's own keys may move what it shows off tau (RetimedCurve::keys).
  std::vector<double> source_frame;
  std::vector<int> drawing_start;     // per drawing: its first output frame
  // With a grid: per drawing, the grid frame it starts on and its start time in (fractional)
  // source frames.
  std::vector<int> drawing_start_grid;
  std::vector<double> drawing_time;
  // Per drawing: its tau in source frames (on a grid, a drawing between two output frames has
  // none of its own in source_frame).
  std::vector<double> drawing_tau;
  bool given = false;  // from KomaUchiOptions::given, not computed
};

// Per drawing of `timing`, its tau in source frames (the same for every curve of the timing;
// also for a drawing on a grid that no output frame shows).
std::vector<double> DrawingTaus(const DrawingTiming& timing);

struct RetimedCurve {
  int timing = 0;              // index into KomaUchiResult::timings; -1: a kKeep group's curve
  // Per output frame: the curve at its drawing's time (tau, or the curve's key the drawing
  // carries: core/key_drawings.h).
  std::vector<double> values;
  // Stepped keyframes: one point per drawing at its first frame with its value (motion3:
  // start point, then a stepped segment to each next point). With a grid the points lie at
  // the drawings' exact grid times, and a last point at the clip's last frame holds the last
  // drawing to the end. Empty for a kKeep group's curve (values are then the input's).
  std::vector<CurvePoint> steps;
  // Hold length in frames (grid frames with a grid) -> number of drawings.
  std::map<int, int> hold_histogram;
  // The curve's keys the rule draws (its first, last and extreme keyframes; KeysToDraw), each
  // with the drawing that carries it, in time order; drawn = false for a key that shared its
  // drawing with one of a larger swing. Empty for a dense curve and a kKeep group's curve.
  std::vector<KeyDrawing> keys;
};

// One timing group's answer.
struct TimingGroupResult {
  std::string name;
  std::vector<int> curves;  // indices into set.curves, ascending
  int frames_per_drawing = 3;  // 0 for a kKeep group
  // Index into KomaUchiResult::timings of its n's timing; -1: no curves, or a kKeep group
  // (whose key poses are then empty too).
  int timing = 0;
  std::vector<int> key_frames;       // its key poses, source frames
  std::vector<int> key_grid_frames;  // with a grid
  std::vector<int> key_merged;       // GridKeyPoses::merged
};

struct KomaUchiResult {
  std::vector<int> key_frames;         // the key poses used
  std::vector<DrawingTiming> timings;  // [0] is the default timing; others per distinct n
  std::vector<RetimedCurve> curves;    // in the order of set.curves
  double timing_fps = 0.0;             // the film grid used; 0: none (source frames)
  std::vector<int> key_grid_frames;    // with a grid: per key pose, its grid frame
  std::vector<int> key_merged;         // GridKeyPoses::merged of the key poses used
  // When some curve is in a named timing group: the default group (its key poses are the
  // ones above, its first timing timings[0]), then options.groups in order. Else empty.
  std::vector<TimingGroupResult> groups;
};

// Requires ValidateCurveSet and ValidateKomaUchiOptions OK.
KomaUchiResult RetimeCurves(const CurveSet& set, const KomaUchiOptions& options);

}  // namespace koma

#endif  // KOMA_CORE_KOMA_UCHI_H_
