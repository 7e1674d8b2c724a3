#pragma once
// What every importer fuzz target checks on its result: an error is one non-empty line; a
// success is a valid model, and small ones mesh or fail with an error (never crash).
#include <cstdlib>
#include <string>

#include "vessel/hclm.hpp"
#include "vessel/vessel_mesher.hpp"
#include "vessel_import/importer.hpp"

namespace cathbox::vessel_import::fuzz {

inline void check(const ImportResult& r) {
  if (!r.ok()) {
    const std::string line = r.errors.front().to_string();
    if (r.errors.front().message.empty() || line.find('\n') != std::string::npos) std::abort();
    return;
  }
  if (!vessel::validate_model(r.model).empty()) std::abort();
  if (r.summary().empty()) std::abort();
  if (r.model.segments.size() <= 6 && r.model.point_count() <= 60) {
    vessel::MeshOptions options;
    options.ring_points = 4;
    options.subdivision_level = 1;
    const vessel::VesselSurface surface = vessel::build_vessel_surface(r.model, options);
    if (!surface.ok() && surface.error.empty()) std::abort();
  }
}

}  // namespace cathbox::vessel_import::fuzz
