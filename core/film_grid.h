// The film grid (docs/semantics.md, "The film grid"): anime timing is counted on a 24 fps
// film whatever rate the source was recorded or authored at, so "on threes" is 8 drawings a
// second on a 30 fps Live2D motion and on 120 fps mocap alike. All three RPCs run their
// algorithm on grid frames and map the result back to source frames with this class.
//
// Exact and machine-independent: the ratio of the two rates is replaced by a fraction p / q
// within 1e-4 of it (relative; the first continued-fraction convergent that close), and every
// mapping is integer arithmetic on p and q. So a BVH Frame Time of 0.0166667 (59.9999 fps)
// maps exactly like 1/60, and ties ("nearest, ties to the earlier") are real ties, not
// accidents of rounding.
#ifndef KOMA_CORE_FILM_GRID_H_
#define KOMA_CORE_FILM_GRID_H_

#include <cstdint>
#include <optional>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"

namespace koma {

inline constexpr double kDefaultTimingFps = 24.0;  // the film's rate, frames per second
inline constexpr double kMaxTimingFps = 1000.0;
// Rates within this relative difference count as equal (BVH Frame Times 0.041667, 0.0416667
// and 0.04166667 are all 24 fps).
inline constexpr double kSameRateTolerance = 1e-4;

// Source rates a grid can count, frames per second: a frame every 1000 s to a million a second.
inline constexpr double kMinSourceFps = 1e-3;
inline constexpr double kMaxSourceFps = 1e6;

// INVALID_ARGUMENT naming `field` when source_fps is outside kMinSourceFps .. kMaxSourceFps
// (a grid is then impossible; the caller checks this only when a grid is asked for).
absl::Status ValidateSourceFps(double source_fps, absl::string_view field);

// INVALID_ARGUMENT "<field>: <value> must be finite and <= 1000 frames per second".
absl::Status ValidateTimingFps(double timing_fps, absl::string_view field);

class FilmGrid {
 public:
  // The grid for a source at `source_fps` (within kMinSourceFps .. kMaxSourceFps) counted at
  // `timing_fps`; nullopt when timing_fps <= 0 or equals source_fps within
  // kSameRateTolerance (count in source frames), or when source_fps is out of range.
  static std::optional<FilmGrid> Make(double source_fps, double timing_fps);

  double source_fps() const { return source_fps_; }
  double timing_fps() const { return timing_fps_; }

  // Grid frames within a clip of `source_frames` frames: those at or before the last source
  // frame's time. >= 1 for source_frames >= 1; saturates at INT_MAX (as do the mappings to
  // frame numbers below) instead of wrapping.
  int GridFrameCount(int source_frames) const;
  // The source frame nearest grid frame g's time (ties to the earlier), at most `last`.
  int NearestSourceFrame(int g, int last) const;
  // The grid frame source frame k falls in: the last one at or before its time.
  int GridFrameOf(int k) const;
  // The grid frame nearest a source time in frames (ties to the earlier), at least 0.
  int NearestGridFrame(double source_frame) const;
  // Grid frame g's time in source frames (fractional): g * source_fps / timing_fps.
  double SourceTime(double g) const;
  // The first source frame at or after grid frame g's time.
  int FirstSourceFrameAtOrAfter(int g) const;

 private:
  FilmGrid(double source_fps, double timing_fps, int64_t p, int64_t q)
      : source_fps_(source_fps), timing_fps_(timing_fps), p_(p), q_(q) {}

  double source_fps_ = 0;
  double timing_fps_ = 0;
  // Source frames per grid frame = p_ / q_ (in lowest terms).
  int64_t p_ = 1;
  int64_t q_ = 1;
};

}  // namespace koma

#endif  // KOMA_CORE_FILM_GRID_H_
