#include "app/mesh_chunks.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <glm/common.hpp>
#include <glm/vec4.hpp>

namespace cathbox::app {

ChunkedMesh ChunkedMesh::build(std::span<const glm::vec3> positions_mm,
                               std::span<const std::uint32_t> triangles, float cell_mm) {
  ChunkedMesh out;
  const std::size_t n = triangles.size() / 3;
  const std::size_t vcount = positions_mm.size();
  glm::vec3 lo(1e30F);
  std::vector<std::uint32_t> valid;
  valid.reserve(n);
  for (std::size_t t = 0; t < n; ++t) {
    const std::uint32_t* f = &triangles[3 * t];
    if (f[0] >= vcount || f[1] >= vcount || f[2] >= vcount) continue;
    valid.push_back(static_cast<std::uint32_t>(t));
    for (int k = 0; k < 3; ++k) lo = glm::min(lo, positions_mm[f[k]]);
  }
  if (valid.empty()) return out;
  const float cell = cell_mm > 0.0F ? cell_mm : 1.0F;
  auto key_of = [&](std::uint32_t t) {
    const std::uint32_t* f = &triangles[3 * static_cast<std::size_t>(t)];
    const glm::vec3 c = (positions_mm[f[0]] + positions_mm[f[1]] + positions_mm[f[2]]) / 3.0F;
    const glm::vec3 g = glm::floor((c - lo) / cell);
    const auto clampi = [](float v) { return static_cast<std::uint64_t>(std::clamp(v, 0.0F, 1048575.0F)); };
    return (clampi(g.z) << 40) | (clampi(g.y) << 20) | clampi(g.x);
  };
  std::vector<std::uint64_t> keys(valid.size());
  for (std::size_t i = 0; i < valid.size(); ++i) keys[i] = key_of(valid[i]);
  std::vector<std::uint32_t> order(valid.size());
  std::iota(order.begin(), order.end(), 0U);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });

  out.triangles.reserve(valid.size() * 3);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::uint32_t t = valid[order[i]];
    const std::uint32_t* f = &triangles[3 * static_cast<std::size_t>(t)];
    if (i == 0 || keys[order[i]] != keys[order[i - 1]]) {
      MeshChunk c;
      c.first_index = static_cast<std::uint32_t>(out.triangles.size());
      c.min_mm = glm::vec3(1e30F);
      c.max_mm = glm::vec3(-1e30F);
      out.chunks.push_back(c);
    }
    MeshChunk& c = out.chunks.back();
    for (int k = 0; k < 3; ++k) {
      out.triangles.push_back(f[k]);
      c.min_mm = glm::min(c.min_mm, positions_mm[f[k]]);
      c.max_mm = glm::max(c.max_mm, positions_mm[f[k]]);
    }
    c.index_count += 3;
  }
  return out;
}

bool box_in_frustum(const glm::mat4& vp, const glm::vec3& lo, const glm::vec3& hi) {
  // Count, for each of the 6 clip planes, the corners outside it.
  int outside[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < 8; ++i) {
    const glm::vec4 c = vp * glm::vec4((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z, 1.0F);
    outside[0] += c.x < -c.w ? 1 : 0;
    outside[1] += c.x > c.w ? 1 : 0;
    outside[2] += c.y < -c.w ? 1 : 0;
    outside[3] += c.y > c.w ? 1 : 0;
    outside[4] += c.z < -c.w ? 1 : 0;
    outside[5] += c.z > c.w ? 1 : 0;
  }
  return std::none_of(std::begin(outside), std::end(outside), [](int k) { return k == 8; });
}

void visible_ranges(std::span<const MeshChunk> chunks, const glm::mat4& view_projection,
                    const glm::vec3& eye_mm, float max_distance_mm, std::vector<IndexRange>& out) {
  out.clear();
  for (const MeshChunk& c : chunks) {
    if (max_distance_mm > 0.0F) {
      const glm::vec3 nearest = glm::clamp(eye_mm, c.min_mm, c.max_mm);
      const glm::vec3 d = nearest - eye_mm;
      if (d.x * d.x + d.y * d.y + d.z * d.z > max_distance_mm * max_distance_mm) continue;
    }
    if (!box_in_frustum(view_projection, c.min_mm, c.max_mm)) continue;
    if (!out.empty() && out.back().first_index + out.back().index_count == c.first_index) {
      out.back().index_count += c.index_count;
    } else {
      out.push_back({c.first_index, c.index_count});
    }
  }
}

}  // namespace cathbox::app
