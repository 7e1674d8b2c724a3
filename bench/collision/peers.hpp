#pragma once
// The benchmark's peers behind one small interface: Embree 3 (rtcPointQuery with a closest-
// point-on-triangle callback) and FCL 0.7 (BVHModel<OBBRSS> distance to a tiny sphere).
#include <memory>

#include <glm/vec3.hpp>

#include "vessel/surface_mesh.hpp"

namespace cathbox::collision::bench {

class PeerIndex {
 public:
  virtual ~PeerIndex() = default;
  // Unsigned distance from p to the mesh.
  [[nodiscard]] virtual double distance(const glm::dvec3& p) = 0;
};

[[nodiscard]] std::unique_ptr<PeerIndex> make_embree(const vessel::SurfaceMesh& mesh);
[[nodiscard]] std::unique_ptr<PeerIndex> make_fcl(const vessel::SurfaceMesh& mesh);

}  // namespace cathbox::collision::bench
