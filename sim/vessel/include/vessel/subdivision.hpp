#pragma once
// Catmull-Clark subdivision of the control mesh with OpenSubdiv (Far::TopologyRefiner, uniform
// refinement, Far::PrimvarRefiner for the refined positions, then limit positions and normals).
// The result is the refined mesh's vertices moved to the limit surface, each quad split into two
// triangles along its shorter diagonal.
#include <functional>
#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "base/result.hpp"
#include "vessel/control_mesh.hpp"
#include "vessel/mesh_options.hpp"
#include "vessel/surface_mesh.hpp"

namespace cathbox::vessel {

// The subdivided surface, or one line saying why there is none.
using SurfaceMeshResult = base::Result<SurfaceMesh>;

// LimitMethod (how the refined vertices go to the limit surface) is in mesh_options.hpp.


// One refinement level's vertices and faces, as a LevelAdjuster sees them. Uniform refinement
// numbers faces by parent: at level k >= 1 a control face of n vertices has the n 4^(k-1)
// consecutive faces after those of the control faces before it (level 0 is the control mesh).
class RefinedLevel {
 public:
  virtual ~RefinedLevel() = default;
  [[nodiscard]] virtual int level() const = 0;
  [[nodiscard]] virtual int face_count() const = 0;
  [[nodiscard]] virtual int vertex_count() const = 0;
  // Counter-clockwise seen from outside; quads from level 1 on.
  [[nodiscard]] virtual std::span<const int> face_vertices(int face) const = 0;
  [[nodiscard]] virtual int vertex_face_count(int vertex) const = 0;
  [[nodiscard]] virtual bool boundary_vertex(int vertex) const = 0;  // on an open edge
  [[nodiscard]] virtual glm::vec3 point(int vertex) const = 0;
  virtual void set_point(int vertex, const glm::vec3& p_mm) = 0;
};
// Called once with level L-1 just before the last refinement step (may move its points).
using LevelAdjuster = std::function<void(RefinedLevel&)>;

// level 0 returns the control mesh itself, triangulated (normals from the faces).
[[nodiscard]] SurfaceMeshResult subdivide(const ControlMesh& control, int level,
                                          LimitMethod method = LimitMethod::kMasks,
                                          const LevelAdjuster& before_last_step = {});

}  // namespace cathbox::vessel
