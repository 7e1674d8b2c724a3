#pragma once
// The vessel surface as the rest of the simulator sees it: a closed, outward-oriented
// triangle mesh in millimetres, with per-vertex normals and, for every triangle, the part of
// the vessel network it belongs to (a segment, a junction or an end cap).
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::vessel {

enum class RegionKind : std::uint8_t {
  kSegment = 0,   // id is the HCLM segment id (the `g` line)
  kJunction = 1,  // id is the junction's index in the vessel graph
  kCap = 2,       // id is the HCLM segment id whose free end the cap closes
};

struct FaceRegion {
  RegionKind kind = RegionKind::kSegment;
  std::int32_t id = 0;
  friend bool operator==(const FaceRegion&, const FaceRegion&) = default;
};

struct SurfaceMesh {
  std::vector<glm::vec3> positions_mm;        // vertex positions
  std::vector<glm::vec3> normals;             // unit outward normal per vertex
  std::vector<std::uint32_t> triangles;       // 3 indices per triangle, counter-clockwise seen from outside
  std::vector<FaceRegion> triangle_regions;   // one per triangle

  [[nodiscard]] std::size_t triangle_count() const { return triangles.size() / 3; }
  [[nodiscard]] std::size_t vertex_count() const { return positions_mm.size(); }
};

}  // namespace cathbox::vessel
