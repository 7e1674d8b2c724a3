// polygon_soup_from_cells(): a VTK surface's polygon cells, checked, as the polygon soup the
// surface importer repairs (surface_import.hpp). No VTK and no CGAL here (fuzzed on its own:
// tests/fuzz/vessel_import/polygon_cells_fuzz.cpp).
#include <cmath>

#include "vessel_import/surface_import.hpp"

namespace cathbox::vessel_import {

PolygonSoup polygon_soup_from_cells(const std::vector<glm::dvec3>& points,
                                    const std::vector<std::vector<std::int64_t>>& polygons, const std::string& file,
                                    std::vector<ImportError>& errors) {
  PolygonSoup soup;
  const auto fail = [&](std::string message) {
    errors.push_back({file, 0, 0, std::move(message)});
    return PolygonSoup{};
  };
  if (polygons.size() > kMaxSurfacePolygons) {
    return fail(std::to_string(polygons.size()) + " polygons: more than " + std::to_string(kMaxSurfacePolygons));
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3& p = points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return fail("point " + std::to_string(i) + " is not a finite position");
    }
  }
  soup.points = points;
  soup.polygons.reserve(polygons.size());
  for (std::size_t c = 0; c < polygons.size(); ++c) {
    const std::vector<std::int64_t>& cell = polygons[c];
    if (cell.size() < 3) return fail("polygon " + std::to_string(c) + " has " + std::to_string(cell.size()) + " points (at least 3)");
    std::vector<std::size_t> ids;
    ids.reserve(cell.size());
    for (const std::int64_t id : cell) {
      if (id < 0 || static_cast<std::uint64_t>(id) >= points.size()) {
        return fail("polygon " + std::to_string(c) + ": point id " + std::to_string(id) + " is not among the " +
                    std::to_string(points.size()) + " points");
      }
      ids.push_back(static_cast<std::size_t>(id));
    }
    soup.polygons.push_back(std::move(ids));
  }
  return soup;
}

}  // namespace cathbox::vessel_import
