// A small radix-2 FFT that gives the same bits on every machine: its twiddle factors come from
// half-angle formulas and products (+ - * / and sqrt only, each correctly rounded by IEEE 754),
// never from libm's cos and sin (whose last bit may differ between libraries and CPUs), and its
// butterflies run in one fixed order. For the short spectra of the voice features (256 points
// per grid frame), where FFTW's run-time SIMD choice would change the bits.
#ifndef KOMA_CORE_SMALL_FFT_H_
#define KOMA_CORE_SMALL_FFT_H_

#include <vector>

#include "absl/types/span.h"

namespace koma {

class SmallFft {
 public:
  // n a power of two, 2 .. 4096.
  explicit SmallFft(int n);

  int size() const { return n_; }
  // cos(2 pi k / n) and sin(2 pi k / n) for k in [0, n), deterministic (within 1e-12 of exact).
  double Cos(int k) const { return cos_[k]; }
  double Sin(int k) const { return sin_[k]; }

  // In place: re + i im -> sum_t (re[t] + i im[t]) e^(-2 pi i k t / n). Both spans of size().
  void Forward(absl::Span<double> re, absl::Span<double> im) const;

 private:
  int n_ = 0;
  std::vector<double> cos_, sin_;  // per k in [0, n)
  std::vector<int> reversed_;      // bit-reversed index of each t
};

// The spectrum of n real samples through one complex FFT of n / 2 points (the even samples
// as real parts, the odd as imaginary, then untangled): half SmallFft's work, the same
// determinism.
class RealFft {
 public:
  // n a power of two, 4 .. 4096.
  explicit RealFft(int n);

  int size() const { return n_; }
  // x (size()) -> bins 0 .. size() / 2 of sum_t x[t] e^(-2 pi i k t / n) into re and im (each
  // size() / 2 + 1).
  void Forward(absl::Span<const double> x, absl::Span<double> re, absl::Span<double> im);

 private:
  int n_ = 0;
  SmallFft twiddles_;  // of n: e^(2 pi i k / n)
  SmallFft half_;      // the transform of n / 2
  std::vector<double> zr_, zi_;
};

}  // namespace koma

#endif  // KOMA_CORE_SMALL_FFT_H_
