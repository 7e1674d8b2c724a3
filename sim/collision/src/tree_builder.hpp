#pragma once
// Builds the flat TreeData of an ObbTree from a SurfaceMesh (validation, topology,
// pseudo-normals, the region-then-median binary OBB tree, and its 4-wide flattening).
#include "collision/obb_tree.hpp"

namespace cathbox::collision {

class TreeBuilder {
 public:
  [[nodiscard]] static TreeBuild build(const vessel::SurfaceMesh& mesh, const BuildOptions& options,
                                       TreeCache* cache = nullptr);
};

}  // namespace cathbox::collision
