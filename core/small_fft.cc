#include "core/small_fft.h"

#include <cmath>
#include <utility>

namespace koma {

SmallFft::SmallFft(int n) : n_(n), cos_(n), sin_(n), reversed_(n) {
  // The angle 2 pi / n by halving pi / 2 (cos 0, sin 1): cos(a / 2) = sqrt((1 + cos a) / 2),
  // sin(a / 2) = sin a / (2 cos(a / 2)); then e^(2 pi i k / n) as successive products with it
  // (the quarter turns exact): about 2e-16 of error per step, so under 1e-12 at n = 4096, and
  // the same bits everywhere.
  double c = 0.0, s = 1.0;  // the angle pi / 2
  for (int quarter = 4; quarter < n; quarter *= 2) {
    const double half_c = std::sqrt((1.0 + c) / 2.0);
    s = s / (2.0 * half_c);
    c = half_c;
  }
  // c + i s = e^(2 pi i / n) (n >= 4); n = 2: e^(pi i) = -1.
  if (n == 2) c = -1.0, s = 0.0;
  cos_[0] = 1.0;
  sin_[0] = 0.0;
  for (int k = 1; k < n; ++k) {
    if (4 * k == n) {
      cos_[k] = 0.0, sin_[k] = 1.0;
    } else if (2 * k == n) {
      cos_[k] = -1.0, sin_[k] = 0.0;
    } else if (4 * k == 3 * n) {
      cos_[k] = 0.0, sin_[k] = -1.0;
    } else {
      cos_[k] = cos_[k - 1] * c - sin_[k - 1] * s;
      sin_[k] = sin_[k - 1] * c + cos_[k - 1] * s;
    }
  }
  int bits = 0;
  while ((1 << bits) < n) ++bits;
  for (int t = 0; t < n; ++t) {
    int r = 0;
    for (int b = 0; b < bits; ++b) r |= ((t >> b) & 1) << (bits - 1 - b);
    reversed_[t] = r;
  }
}

void SmallFft::Forward(absl::Span<double> re, absl::Span<double> im) const {
  for (int t = 0; t < n_; ++t) {
    const int r = reversed_[t];
    if (r > t) {
      std::swap(re[t], re[r]);
      std::swap(im[t], im[r]);
    }
  }
  for (int length = 2; length <= n_; length *= 2) {
    const int half = length / 2, step = n_ / length;
    for (int start = 0; start < n_; start += length) {
      for (int j = 0; j < half; ++j) {
        // The twiddle e^(-2 pi i j / length) = cos - i sin of k = j x step.
        const double wr = cos_[j * step], wi = -sin_[j * step];
        const int a = start + j, b = a + half;
        const double xr = re[b] * wr - im[b] * wi;
        const double xi = re[b] * wi + im[b] * wr;
        re[b] = re[a] - xr;
        im[b] = im[a] - xi;
        re[a] += xr;
        im[a] += xi;
      }
    }
  }
}

RealFft::RealFft(int n) : n_(n), twiddles_(n), half_(n / 2), zr_(n / 2), zi_(n / 2) {}

void RealFft::Forward(absl::Span<const double> x, absl::Span<double> re,
                      absl::Span<double> im) {
  const int m = n_ / 2;
  for (int t = 0; t < m; ++t) {
    zr_[t] = x[2 * t];
    zi_[t] = x[2 * t + 1];
  }
  half_.Forward(absl::MakeSpan(zr_), absl::MakeSpan(zi_));
  // With Z the transform of z[t] = x[2t] + i x[2t + 1]: the even samples' spectrum is
  // E = (Z[k] + conj Z[m - k]) / 2, the odd's O = (Z[k] - conj Z[m - k]) / 2i, and
  // X[k] = E + e^(-2 pi i k / n) O.
  for (int k = 0; k <= m; ++k) {
    const int a = k % m, b = (m - k) % m;
    const double er = 0.5 * (zr_[a] + zr_[b]), ei = 0.5 * (zi_[a] - zi_[b]);
    const double orr = 0.5 * (zi_[a] + zi_[b]), oi = -0.5 * (zr_[a] - zr_[b]);
    const double wr = twiddles_.Cos(k), wi = -twiddles_.Sin(k);
    re[k] = er + (orr * wr - oi * wi);
    im[k] = ei + (orr * wi + oi * wr);
  }
}

}  // namespace koma
