// The fluoroscopic view's image-model parts that need no GL: the per-pulse noise (its
// statistics, determinism, independence between pulses and pixels) and the thin-line rule.
#include <gtest/gtest.h>

#include <cmath>

#include "app/fluoro_image_model.hpp"

namespace cathbox::app {
namespace {

TEST(FluoroNoise, IsStandardNormalDeterministicAndNewEveryPulse) {
  const std::uint32_t seed = pulse_seed(42);
  EXPECT_EQ(seed, pulse_seed(42));
  EXPECT_NE(seed, pulse_seed(43));
  double sum = 0.0;
  double sum2 = 0.0;
  double sum4 = 0.0;
  double neighbours = 0.0;
  double pulses = 0.0;
  const std::uint32_t other = pulse_seed(43);
  constexpr int kN = 512;
  for (std::uint32_t y = 0; y < kN; ++y) {
    for (std::uint32_t x = 0; x < kN; ++x) {
      const double n = pixel_noise(x, y, seed);
      EXPECT_EQ(n, pixel_noise(x, y, seed));
      sum += n;
      sum2 += n * n;
      sum4 += n * n * n * n;
      neighbours += n * pixel_noise(x + 1, y, seed);
      pulses += n * pixel_noise(x, y, other);
    }
  }
  const double count = kN * kN;
  EXPECT_NEAR(sum / count, 0.0, 0.01);
  EXPECT_NEAR(sum2 / count, 1.0, 0.01);
  // Irwin-Hall with n = 4 has kurtosis 3 - 1.2 / 4 = 2.7 (a normal one 3).
  EXPECT_NEAR(sum4 / count, 2.7, 0.05);
  EXPECT_NEAR(neighbours / count, 0.0, 0.01) << "neighbouring pixels independent";
  EXPECT_NEAR(pulses / count, 0.0, 0.01) << "successive pulses independent";
}

TEST(ThinLine, WidensToAPixelKeepingTheAttenuationAcrossTheLine) {
  const ThinLine wide = thin_line(0.5F, 0.16);
  EXPECT_EQ(wide.radius_mm, 0.5F);
  EXPECT_EQ(wide.mu_scale, 1.0F);
  const ThinLine thin = thin_line(0.1F, 0.16);
  EXPECT_FLOAT_EQ(thin.radius_mm, 0.16F);
  // mu * pi r^2 kept.
  EXPECT_NEAR(thin.mu_scale * thin.radius_mm * thin.radius_mm, 0.1F * 0.1F, 1e-7);
}

// The detector's binned readout: a display finer than the readout pitch gets the readout's
// pixels (the same aspect), a coarser one its own, and a pitch of 0 never bins.
TEST(ReadoutMatrix, BinsOnlyWhereTheDisplayIsFinerThanTheReadout) {
  const ImageMatrix binned = readout_matrix(1000, 600, 0.2, 0.4);
  EXPECT_EQ(binned.width, 500);
  EXPECT_EQ(binned.height, 300);
  const ImageMatrix coarse = readout_matrix(1000, 600, 0.5, 0.4);
  EXPECT_EQ(coarse.width, 1000);
  EXPECT_EQ(coarse.height, 600);
  EXPECT_EQ(readout_matrix(7, 5, 0.2, 0.0).width, 7);
  EXPECT_EQ(readout_matrix(1, 1, 0.01, 0.4).height, 1);  // never below one pixel
}

}  // namespace
}  // namespace cathbox::app
