// sin and cos of an angle in degrees, computed with +, -, *, / and exact reductions only, so
// the bits are the same with every libm: glibc, musl and others round sin/cos differently in
// the last place, and forward kinematics feeds those bits into distances, ties and the
// response (input_ssd). Accurate to about 1 ulp; exact at multiples of 90 degrees
// (sin 90 = 1, cos 90 = 0), which libm's radians-based functions are not.
#ifndef KOMA_CORE_TRIG_DEGREES_H_
#define KOMA_CORE_TRIG_DEGREES_H_

namespace koma {

struct SinCos {
  double sin = 0.0;
  double cos = 1.0;
};

// Any finite `degrees`. One angle at a time (the batch form below is the fast one).
SinCos SinCosDegrees(double degrees);

// SinCosDegrees of each of degrees[0..n), bit for bit, into sin[i] and cos[i] (which must
// not overlap `degrees`). Written as one branch-free loop the compiler vectorises: forward
// kinematics converts a whole frame's channels at once.
void SinCosDegrees(const double* degrees, int n, double* sin, double* cos);

}  // namespace koma

#endif  // KOMA_CORE_TRIG_DEGREES_H_
