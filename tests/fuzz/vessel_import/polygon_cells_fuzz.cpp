// Fuzzes what the VTK importer does with a surface after VTK has read it: points and polygon
// cells (decoded from the bytes: points as signed bytes in mm, cells as point ids that may be
// out of range or too few) to the checked polygon soup, then, for small soups, the surface
// import (CGAL's repair, capping and skeleton) and the network, as the importer does.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_check.hpp"
#include "vessel_import/surface_import.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace cathbox::vessel_import;
  size_t at = 0;
  const auto next = [&]() -> uint8_t { return at < size ? data[at++] : 0; };
  std::vector<glm::dvec3> points;
  const int n_points = next() % 48;
  for (int i = 0; i < n_points; ++i) {
    const auto coord = [&] { return 0.5 * static_cast<int8_t>(next()); };
    const double x = coord(), y = coord(), z = coord();
    points.emplace_back(x, y, z);
  }
  std::vector<std::vector<std::int64_t>> polygons;
  const int n_polygons = next() % 64;
  for (int c = 0; c < n_polygons && at < size; ++c) {
    std::vector<std::int64_t> cell;
    const int length = next() % 7;
    for (int k = 0; k < length; ++k) cell.push_back(static_cast<std::int64_t>(next()) - 2);  // -2 .. 253
    polygons.push_back(std::move(cell));
  }
  ImportResult result;
  PolygonSoup soup = polygon_soup_from_cells(points, polygons, "fuzz.vtp", result.errors);
  if (!result.ok()) {
    fuzz::check(result);
    return 0;
  }
  if (soup.polygons.size() != polygons.size() || soup.points.size() != points.size()) std::abort();
  const SurfaceImport imported = import_surface_soup(std::move(soup), "fuzz.vtp", SurfaceOptions{});
  if (!imported.ok()) {
    result.errors = imported.errors;
    fuzz::check(result);
    return 0;
  }
  if (imported.lumen.triangle_count() == 0 || imported.lumen.triangle_regions.size() != imported.lumen.triangle_count()) {
    std::abort();
  }
  return 0;
}
