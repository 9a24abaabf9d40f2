// Which samples of a recording fall in which film-grid frame, in integers: frame g holds samples
// [FirstSample(g), FirstSample(g + 1)), FirstSample(g) = ceil(g x sample_rate / frame_fps), with
// frame_fps as a fraction num / den (exact for integer rates and NTSC's 24000 / 1001; else the
// nearest with den <= 10^6), so the boundaries are the same on every machine and do not drift
// over an hour. Shared by the per-frame loudness and the voice features, so both see the same
// frames.
#ifndef KOMA_CORE_GRID_SAMPLES_H_
#define KOMA_CORE_GRID_SAMPLES_H_

#include <cstdint>

namespace koma {

class GridSamples {
 public:
  // sample_rate in 1 .. 1e6 samples per second, frame_fps in (0, 1000] frames per second.
  GridSamples(int sample_rate, double frame_fps);

  // The first sample of `frame` (>= 0); INT64_MAX from frame 2^31 - 1 on.
  int64_t FirstSample(int64_t frame) const;
  int sample_rate() const { return static_cast<int>(rate_); }

 private:
  int64_t rate_ = 1;                   // samples per second
  int64_t fps_num_ = 1, fps_den_ = 1;  // frame_fps = fps_num_ / fps_den_
};

}  // namespace koma

#endif  // KOMA_CORE_GRID_SAMPLES_H_
