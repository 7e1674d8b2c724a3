#include "app/fluoro_image_model.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::app {
ImageMatrix readout_matrix(int width, int height, double display_pixel_mm, double readout_pitch_mm) {
  if (!(readout_pitch_mm > display_pixel_mm)) return {width, height};
  const double scale = display_pixel_mm / readout_pitch_mm;
  return {std::max(1, static_cast<int>(std::lround(width * scale))), std::max(1, static_cast<int>(std::lround(height * scale)))};
}

ThinLine thin_line(float radius_mm, double patient_pixel_mm, double min_px) {
  const auto floor_mm = static_cast<float>(min_px * patient_pixel_mm);
  if (radius_mm >= floor_mm || radius_mm <= 0.0F) return {radius_mm, 1.0F};
  const float k = radius_mm / floor_mm;
  return {floor_mm, k * k};
}

std::uint32_t pulse_seed(std::int64_t pulse) {
  // splitmix64's finaliser, folded to 32 bits.
  auto z = static_cast<std::uint64_t>(pulse) + 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
  z ^= z >> 31U;
  return static_cast<std::uint32_t>(z ^ (z >> 32U));
}

float pixel_noise(std::uint32_t x, std::uint32_t y, std::uint32_t seed) {
  // As the composite shader (fluoro_renderer.cpp, noise()): unsigned 32-bit arithmetic.
  std::uint32_t h = (x * 0x8DA6B343U) ^ (y * 0xD8163841U) ^ seed;
  h ^= h >> 16U;
  h *= 0x7FEB352DU;
  h ^= h >> 15U;
  h *= 0x846CA68BU;
  h ^= h >> 16U;
  const std::uint32_t bytes = (h & 0xFFU) + ((h >> 8U) & 0xFFU) + ((h >> 16U) & 0xFFU) + (h >> 24U);
  // Four uniform bytes: mean 510, variance 4 * (256^2 - 1) / 12.
  return (static_cast<float>(bytes) - 510.0F) * 0.0067659F;
}

}  // namespace cathbox::app
