#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/common.hpp>

#include "app/fluoro_renderer.hpp"

// FluoroRenderer::prepare_vessel: the vessel's vertex and index buffers, with no GL (any thread).

namespace cathbox::app {
namespace {

constexpr std::size_t kBucketTriangles = 256;  // vessel triangles culled together by their cells

}  // namespace

FluoroRenderer::VesselBuffers FluoroRenderer::prepare_vessel(const FluoroVessel& vessel) {
  VesselBuffers out;
  std::vector<float>& v = out.vertices;
  v.resize(vessel.positions_mm.size() * 6);
  for (std::size_t i = 0; i < vessel.positions_mm.size(); ++i) {
    float* o = v.data() + 6 * i;
    const glm::vec3& p = vessel.positions_mm[i];
    const VertexCells c = i < vessel.cells.size() ? vessel.cells[i] : VertexCells{};
    o[0] = p.x;
    o[1] = p.y;
    o[2] = p.z;
    o[3] = static_cast<float>(c.a);
    o[4] = static_cast<float>(c.b);
    o[5] = c.w;
  }
  // Triangles sorted by the lowest contrast cell they read, in buckets that know the range of
  // cells they read: a pulse draws only the buckets with iodine in their range (a face whose
  // vertices have none adds nothing).
  const std::size_t triangles = vessel.triangles.size() / 3;
  std::vector<std::uint32_t> order(triangles);
  std::vector<std::uint32_t> lo(triangles, 0xFFFFFFFFU);
  std::vector<std::uint32_t> hi(triangles, 0);
  for (std::size_t t = 0; t < triangles; ++t) {
    order[t] = static_cast<std::uint32_t>(t);
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t vi = vessel.triangles[3 * t + k];
      const VertexCells c = vi < vessel.cells.size() ? vessel.cells[vi] : VertexCells{};
      lo[t] = std::min({lo[t], c.a, c.b});
      hi[t] = std::max({hi[t], c.a, c.b});
    }
  }
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return lo[x] < lo[y]; });
  std::vector<std::uint32_t>& sorted = out.indices;
  sorted.reserve(vessel.triangles.size());
  for (std::size_t i = 0; i < triangles; ++i) {
    const std::uint32_t t = order[i];
    const glm::vec3& p0 = vessel.positions_mm[vessel.triangles[3 * t]];
    if (i % kBucketTriangles == 0) out.buckets.push_back({static_cast<std::uint32_t>(3 * i), 0, lo[t], hi[t], p0, p0});
    Bucket& b = out.buckets.back();
    b.index_count += 3;
    b.lo = std::min(b.lo, lo[t]);
    b.hi = std::max(b.hi, hi[t]);
    for (int k = 0; k < 3; ++k) {
      const glm::vec3& p = vessel.positions_mm[vessel.triangles[3 * t + k]];
      b.box_min = glm::min(b.box_min, p);
      b.box_max = glm::max(b.box_max, p);
    }
    sorted.insert(sorted.end(), {vessel.triangles[3 * t], vessel.triangles[3 * t + 1], vessel.triangles[3 * t + 2]});
  }
  out.cell_count = vessel.cell_count;
  return out;
}

}  // namespace cathbox::app
