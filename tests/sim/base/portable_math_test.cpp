// base/portable_math.hpp against the platform's libm (the reference: glibc's, correctly
// rounded or within 1 ulp): within 8 ulp on the angles the rod uses, exact where the answer is
// (0, the axes), NaN outside the domain; and a fixed fingerprint of two million results, which
// the WebAssembly build reproduces (tests/host/wasm: the replays match hash for hash).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <functional>
#include <limits>

#include "base/portable_math.hpp"

namespace cathbox::base::portable {
namespace {

double ulps(double got, double want) {
  if (got == want) return 0.0;
  const double ulp = std::nextafter(std::fabs(want), std::numeric_limits<double>::infinity()) - std::fabs(want);
  return std::fabs(got - want) / ulp;
}

// The worst error over n arguments spread over [lo, hi] by a low-discrepancy walk.
double worst_ulps(const std::function<double(double)>& mine, const std::function<double(double)>& libm, double lo,
                  double hi, int n = 200000) {
  double worst = 0.0;
  double u = 0.5;
  for (int i = 0; i < n; ++i) {
    u = std::fmod(u + 0.6180339887498949, 1.0);
    const double x = lo + (hi - lo) * u;
    worst = std::max(worst, ulps(mine(x), libm(x)));
  }
  return worst;
}

TEST(PortableMath, WithinEightUlpOfLibm) {
  EXPECT_LE(worst_ulps([](double x) { return sin(x); }, [](double x) { return std::sin(x); }, -40.0, 40.0), 8.0);
  EXPECT_LE(worst_ulps([](double x) { return cos(x); }, [](double x) { return std::cos(x); }, -40.0, 40.0), 8.0);
  EXPECT_LE(worst_ulps([](double x) { return tan(x); }, [](double x) { return std::tan(x); }, -1.5, 1.5), 8.0);
  EXPECT_LE(worst_ulps([](double x) { return asin(x); }, [](double x) { return std::asin(x); }, -1.0, 1.0), 8.0);
  EXPECT_LE(worst_ulps([](double x) { return acos(x); }, [](double x) { return std::acos(x); }, -1.0, 1.0), 8.0);
  EXPECT_LE(worst_ulps([](double x) { return atan(x); }, [](double x) { return std::atan(x); }, -50.0, 50.0), 8.0);
  EXPECT_LE(worst_ulps([](double x) { return atan2(x, 1.3 - x); }, [](double x) { return std::atan2(x, 1.3 - x); },
                       -20.0, 20.0),
            8.0);
  // Small angles keep their relative accuracy (the rod's nearly straight segments).
  EXPECT_LE(worst_ulps([](double x) { return sin(x); }, [](double x) { return std::sin(x); }, -1e-6, 1e-6), 2.0);
}

TEST(PortableMath, ExactValuesAndDomain) {
  EXPECT_EQ(sin(0.0), 0.0);
  EXPECT_EQ(cos(0.0), 1.0);
  EXPECT_EQ(tan(0.0), 0.0);
  EXPECT_EQ(atan2(0.0, 1.0), 0.0);
  EXPECT_EQ(atan2(0.0, -1.0), detail::kPi);
  EXPECT_EQ(atan2(-0.0, -1.0), -detail::kPi);
  EXPECT_EQ(atan2(1.0, 0.0), detail::kHalfPi);
  EXPECT_EQ(atan2(-1.0, 0.0), -detail::kHalfPi);
  EXPECT_EQ(asin(1.0), detail::kHalfPi);
  EXPECT_EQ(acos(1.0), 0.0);
  EXPECT_TRUE(std::isnan(asin(1.5)));
  EXPECT_TRUE(std::isnan(acos(-1.0000001)));
  EXPECT_TRUE(std::isnan(sin(std::numeric_limits<double>::infinity())));
  EXPECT_TRUE(std::isnan(atan2(std::nan(""), 1.0)));
}

// sincos is sin and cos bit for bit (the rod's material frames take it): every quadrant, either
// sign, up to and past the reduction's range, and off the domain.
TEST(PortableMath, SinCosIsSinAndCosBitForBit) {
  const auto bits = [](double v) {
    std::uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
  };
  double u = 0.5;
  for (const double scale : {1e-6, 1.0, 40.0, 1e4, 5.9e6, 1e7}) {
    for (int i = 0; i < 20000; ++i) {
      u = std::fmod(u + 0.6180339887498949, 1.0);
      const double x = scale * (2.0 * u - 1.0);
      double s = 0.0, c = 0.0;
      sincos(x, s, c);
      ASSERT_EQ(bits(s), bits(sin(x))) << x;
      ASSERT_EQ(bits(c), bits(cos(x))) << x;
    }
  }
  double s = 0.0, c = 0.0;
  sincos(std::numeric_limits<double>::infinity(), s, c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
}

TEST(PortableMath, FingerprintIsFixed) {
  // Folds the bits of two million results; the value is this implementation's, on any platform.
  std::uint64_t h = 0;
  double x = 1e-3;
  for (int i = 0; i < 2'000'000; ++i) {
    x = std::fmod(x * 1.61803398875 + 0.12345, 40.0) - 20.0;
    const double r = sin(x) + cos(x) + tan(0.5 * x) + atan2(x, 1.3 - x) + asin(std::fmod(x, 1.0));
    std::uint64_t b = 0;
    std::memcpy(&b, &r, sizeof b);
    h = (h ^ b) * 0x100000001b3ULL;
  }

  EXPECT_EQ(h, 0x586a458ab1b5d25bULL);
}

}  // namespace
}  // namespace cathbox::base::portable
