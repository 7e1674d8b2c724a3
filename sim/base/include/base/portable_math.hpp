#pragma once
// sin, cos, tan, atan2, asin and acos that give the same bits on every platform: the rod's
// twist and curvature go through them, so a session replays hash for hash between the native
// build (glibc's libm) and the WebAssembly one (musl's), whose libms differ in the last bit of
// some results (a wire turned by a script diverged within 100 ticks). Built only of
// IEEE operations that are correctly rounded everywhere (+ - * /, sqrt, nearbyint), in a fixed
// order, without fused multiply-adds (the project compiles ISO C++, where GCC does not contract;
// WebAssembly has no FMA). Accuracy: within 8 units in the last place of the libm result
// (tests/sim/base/portable_math_test.cpp).
//   sin/cos/tan: x reduced by multiples of pi/2 (pi/2 in three parts, the first two of 30 bits
//   so k * part is exact for |k| < 2^23), then Taylor series to r^17 / r^18 on |r| <= pi/4.
//   atan: |x| > 1 by atan(x) = pi/2 - atan(1/x), then two half-angle steps
//   (atan(x) = 2 atan(x / (1 + sqrt(1 + x^2)))) to |y| <= tan(pi/16), then its series to y^27.
#include <cmath>
#include <initializer_list>
#include <limits>

namespace cathbox::base::portable {

namespace detail {

inline constexpr double kPi = 3.141592653589793;
inline constexpr double kHalfPi = 1.5707963267948966;
inline constexpr double kTwoOverPi = 0.6366197723675814;
inline constexpr double kHalfPi1 = 1.5707963276654482;    // 30 bits
inline constexpr double kHalfPi2 = -8.705515692000731e-10;  // the next 30 bits
inline constexpr double kHalfPi3 = -3.50343439808993e-19;   // the rest

// sin(r) and cos(r) for |r| <= pi/4 (Taylor, Horner in r^2).
inline double sin_kernel(double r) {
  const double z = r * r;
  const double p =
      -0.16666666666666666 +
      z * (0.008333333333333333 +
           z * (-0.0001984126984126984 +
                z * (2.7557319223985893e-06 +
                     z * (-2.505210838544172e-08 +
                          z * (1.6059043836821613e-10 + z * (-7.647163731819816e-13 + z * 2.8114572543455206e-15))))));
  return r + r * z * p;
}

inline double cos_kernel(double r) {
  const double z = r * r;
  const double p =
      0.041666666666666664 +
      z * (-0.001388888888888889 +
           z * (2.48015873015873e-05 +
                z * (-2.755731922398589e-07 +
                     z * (2.08767569878681e-09 +
                          z * (-1.1470745597729725e-11 + z * (4.779477332387385e-14 + z * -1.5619206968586225e-16))))));
  return 1.0 - 0.5 * z + z * z * p;
}

struct Reduced {
  double r;   // x - k pi/2, |r| <= about pi/4
  long q;     // k mod 4
};

inline Reduced reduce(double x) {
  const double k = std::nearbyint(x * kTwoOverPi);
  const double r = ((x - k * kHalfPi1) - k * kHalfPi2) - k * kHalfPi3;
  // k mod 4, in [0, 4): k is a whole number of magnitude below 2^23 (kMaxReduced), so its low
  // two bits in two's complement are fmod(k, 4) taken into [0, 4), without fmod's cost.
  const long q = static_cast<long>(k) & 3L;
  return {r, q};
}

// atan for 0 <= x <= 1.
inline double atan_unit(double x) {
  double y = x / (1.0 + std::sqrt(1.0 + x * x));
  y = y / (1.0 + std::sqrt(1.0 + y * y));
  const double z = y * y;
  double p = -0.037037037037037035;
  for (const double c : {0.04, -0.043478260869565216, 0.047619047619047616, -0.05263157894736842,
                         0.058823529411764705, -0.06666666666666667, 0.07692307692307693, -0.09090909090909091,
                         0.1111111111111111, -0.14285714285714285, 0.2, -0.3333333333333333}) {
    p = c + z * p;
  }
  return 4.0 * (y + y * z * p);
}

// Beyond this the reduction's k * part products are no longer exact.
inline constexpr double kMaxReduced = 6.0e6;

}  // namespace detail

[[nodiscard]] inline double sin(double x) {
  if (!std::isfinite(x)) return std::numeric_limits<double>::quiet_NaN();
  if (std::fabs(x) > detail::kMaxReduced) return std::sin(x);  // far beyond any angle the simulator turns
  const detail::Reduced d = detail::reduce(x);
  switch (d.q) {
    case 0: return detail::sin_kernel(d.r);
    case 1: return detail::cos_kernel(d.r);
    case 2: return -detail::sin_kernel(d.r);
    default: return -detail::cos_kernel(d.r);
  }
}

[[nodiscard]] inline double cos(double x) {
  if (!std::isfinite(x)) return std::numeric_limits<double>::quiet_NaN();
  if (std::fabs(x) > detail::kMaxReduced) return std::cos(x);
  const detail::Reduced d = detail::reduce(x);
  switch (d.q) {
    case 0: return detail::cos_kernel(d.r);
    case 1: return -detail::sin_kernel(d.r);
    case 2: return -detail::cos_kernel(d.r);
    default: return detail::sin_kernel(d.r);
  }
}

// sin(x) and cos(x) at once, bit for bit those of sin and cos above, on one reduction (the rod's
// material frames take both of every edge's angle).
inline void sincos(double x, double& s, double& c) {
  if (!std::isfinite(x) || std::fabs(x) > detail::kMaxReduced) {
    s = sin(x);
    c = cos(x);
    return;
  }
  const detail::Reduced d = detail::reduce(x);
  const double sk = detail::sin_kernel(d.r);
  const double ck = detail::cos_kernel(d.r);
  switch (d.q) {
    case 0: s = sk, c = ck; return;
    case 1: s = ck, c = -sk; return;
    case 2: s = -sk, c = -ck; return;
    default: s = -ck, c = sk; return;
  }
}

[[nodiscard]] inline double tan(double x) {
  if (!std::isfinite(x)) return std::numeric_limits<double>::quiet_NaN();
  if (std::fabs(x) > detail::kMaxReduced) return std::tan(x);
  const detail::Reduced d = detail::reduce(x);
  const double s = detail::sin_kernel(d.r);
  const double c = detail::cos_kernel(d.r);
  return (d.q % 2 == 0) ? s / c : -c / s;
}

[[nodiscard]] inline double atan(double x) {
  if (std::isnan(x)) return x;
  const double a = std::fabs(x);
  const double r = a <= 1.0 ? detail::atan_unit(a) : detail::kHalfPi - detail::atan_unit(1.0 / a);
  return x < 0.0 ? -r : r;
}

[[nodiscard]] inline double atan2(double y, double x) {
  if (std::isnan(x) || std::isnan(y)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0 && y == 0.0) return std::signbit(x) ? std::copysign(detail::kPi, y) : std::copysign(0.0, y);
  const double ay = std::fabs(y);
  const double ax = std::fabs(x);
  // The angle of (ax, ay) in [0, pi/2], from the smaller ratio.
  double a = 0.0;
  if (ay <= ax) {
    a = detail::atan_unit(ay / ax);
  } else {
    a = detail::kHalfPi - detail::atan_unit(ax / ay);
  }
  if (std::signbit(x)) a = detail::kPi - a;
  return std::copysign(a, y);
}

[[nodiscard]] inline double asin(double x) {
  if (std::isnan(x) || std::fabs(x) > 1.0) return std::numeric_limits<double>::quiet_NaN();
  return atan2(x, std::sqrt((1.0 - x) * (1.0 + x)));
}

[[nodiscard]] inline double acos(double x) {
  if (std::isnan(x) || std::fabs(x) > 1.0) return std::numeric_limits<double>::quiet_NaN();
  return atan2(std::sqrt((1.0 - x) * (1.0 + x)), x);
}

}  // namespace cathbox::base::portable
