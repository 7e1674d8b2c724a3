#pragma once
// A surface import's lumen tagged by segment (importer.hpp, ImportResult::lumen).
#include "vessel/surface_mesh.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel_import {

// Each lumen triangle takes the segment whose centreline point is nearest its centroid (searched
// in a grid of cells as wide as the model's widest radius); a model without a positive radius
// leaves the tags as they are.
void tag_lumen_regions(const vessel::VesselModel& model, vessel::SurfaceMesh& lumen);

}  // namespace cathbox::vessel_import
