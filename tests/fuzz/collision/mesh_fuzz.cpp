// Input: [vertex count][triangle count] then 3 floats per vertex, 3 index bytes per triangle
// (taken modulo vertex count + 2, so some are out of range), 1 region byte per triangle, and
// the rest as query floats (points, radii, directions).
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "collision/obb_tree.hpp"

namespace {

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  float real() {
    std::uint8_t b[4] = {byte(), byte(), byte(), byte()};
    float f;
    std::memcpy(&f, b, sizeof f);
    return f;
  }
  [[nodiscard]] bool more() const { return pos_ < size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cathbox;
  Reader in(data, size);
  const int vertices = in.byte() % 48;
  const int triangles = in.byte() % 64;
  vessel::SurfaceMesh mesh;
  for (int v = 0; v < vertices; ++v) mesh.positions_mm.emplace_back(in.real(), in.real(), in.real());
  mesh.normals.assign(mesh.positions_mm.size(), glm::vec3(0.0f, 0.0f, 1.0f));
  for (int t = 0; t < triangles; ++t)
    for (int k = 0; k < 3; ++k) mesh.triangles.push_back(in.byte() % static_cast<std::uint32_t>(vertices + 2));
  for (int t = 0; t < triangles; ++t) {
    const std::uint8_t r = in.byte();
    mesh.triangle_regions.push_back({static_cast<vessel::RegionKind>(r % 3), r / 3});
  }
  const collision::TreeBuild built = collision::ObbTree::build(mesh);
  if (!built) return 0;
  const collision::ObbTree& tree = *built;
  collision::QueryHint hint;
  std::array<collision::Contact, 8> contacts{};
  while (in.more()) {
    const glm::dvec3 p(in.real(), in.real(), in.real());
    const glm::dvec3 q(in.real(), in.real(), in.real());
    const double r = in.real();
    (void)tree.closest_point(p);
    (void)tree.closest_point(p, r, hint);
    (void)tree.signed_distance(q);
    (void)tree.sphere_contacts(p, r, contacts);
    (void)tree.sphere_contacts(q, r, contacts, hint);
    (void)tree.capsule_contacts(p, q, r, contacts, hint);
    (void)tree.ray_cast(p, q - p, r);
  }
  return 0;
}
