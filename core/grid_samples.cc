#include "core/grid_samples.h"

#include <climits>
#include <cmath>

namespace koma {
namespace {

// `fps` as num / den: the first continued-fraction convergent within 1e-12 of it (relative),
// or the last one with den <= 10^6.
void FpsFraction(double fps, int64_t* num, int64_t* den) {
  int64_t p0 = 1, q0 = 0;
  int64_t p1 = static_cast<int64_t>(std::floor(fps)), q1 = 1;
  double rest = fps - std::floor(fps);
  while (rest > 0 && std::fabs(static_cast<double>(p1) / static_cast<double>(q1) - fps) >
                         1e-12 * fps) {
    const double inverse = 1.0 / rest;
    const int64_t a = static_cast<int64_t>(std::floor(inverse));
    if (a > 1000000 || a * q1 + q0 > 1000000) break;
    const int64_t p2 = a * p1 + p0, q2 = a * q1 + q0;
    p0 = p1, q0 = q1, p1 = p2, q1 = q2;
    rest = inverse - std::floor(inverse);
  }
  if (p1 < 1) {  // fps below 1e-6 of a frame per second: not a rate the server takes
    p1 = 1;
    q1 = 1000000;
  }
  *num = p1;
  *den = q1;
}

}  // namespace

GridSamples::GridSamples(int sample_rate, double frame_fps) : rate_(sample_rate) {
  FpsFraction(frame_fps, &fps_num_, &fps_den_);
}

int64_t GridSamples::FirstSample(int64_t frame) const {
  // ceil(frame x rate x den / num) without overflow: frame x rate < 2^31 x 10^6 fits, and
  // splitting it by num keeps each product below 10^9 x 10^6.
  if (frame >= INT32_MAX) return INT64_MAX;
  const int64_t a = frame * rate_;
  const int64_t whole = a / fps_num_, rest = a % fps_num_;
  return whole * fps_den_ + (rest * fps_den_ + fps_num_ - 1) / fps_num_;
}

}  // namespace koma
