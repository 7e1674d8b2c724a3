#pragma once
// A vessel surface (a segmentation's lumen as STL, OBJ, PLY or OFF) into the central axis model:
// the surface is repaired (duplicate vertices merged, winding made consistent and outward, open
// inlets and outlets found and capped), checked (one closed lumen, no self-intersection), and its
// centreline graph extracted with CGAL's mean curvature flow skeleton (Tagliasacchi, Alhashim,
// Olson, Zhang, "Mean Curvature Skeletons", SGP 2012). Each skeleton point's radius is its
// distance to the surface. The branches between skeleton nodes then go through the same network
// clean-up, radius filter and validation as every other importer (importer.hpp).
//
// CGAL is used only in src/surface_skeleton.cpp; this header is plain C++.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/surface_mesh.hpp"
#include "vessel_import/import_error.hpp"
#include "vessel_import/network_builder.hpp"

namespace cathbox::vessel_import {

// Polygons as read (indices into points); triangles and larger polygons alike.
struct PolygonSoup {
  std::vector<glm::dvec3> points;
  std::vector<std::vector<std::size_t>> polygons;
};

// An open end of the surface (an inlet or outlet cut by the segmentation), capped on import.
struct OpenEnd {
  glm::dvec3 centre_mm{0.0};
  double radius_mm = 0.0;  // mean distance of its border from the centre
  std::size_t border_vertices = 0;
};

struct SurfaceStats {
  std::size_t polygons_read = 0;
  std::size_t points_read = 0;
  std::size_t points_merged = 0;     // duplicate points merged (an STL repeats every corner)
  std::size_t polygons_dropped = 0;  // degenerate or duplicate polygons removed
  std::size_t components = 0;        // connected pieces found
  std::size_t components_dropped = 0;
  std::vector<OpenEnd> open_ends;    // capped
  std::size_t triangles = 0;         // of the repaired lumen
  std::size_t skeleton_points = 0;
  double extent_mm = 0.0;            // the bounding box's largest side
  // CPU seconds per stage (std::clock): reading the file, repair (merge, orient, to a mesh, one
  // piece, caps), the closed / self-intersection / outward checks, the flow (simplification of
  // its copy included), walking + centring the skeleton against the full lumen, and the network
  // (clean-up, radius filter, validation, the control mesh check, tagging the lumen's triangles).
  struct Seconds {
    double read = 0.0, repair = 0.0, check = 0.0, flow = 0.0, centre = 0.0, graph = 0.0;
  } seconds;
};

struct SurfaceOptions {
  double unit_mm = 1.0;        // millimetres per unit of the file
  bool keep_largest = false;   // several pieces: keep the largest instead of refusing
};

struct SurfaceImport {
  std::vector<Branch> branches;  // the skeleton's branches, radius = distance to the surface
  vessel::SurfaceMesh lumen;     // the closed, outward lumen after repair (area-weighted normals;
                                 // every triangle in region {kSegment, 0} until tagged)
  SurfaceStats stats;
  std::vector<ImportError> errors;
  [[nodiscard]] bool ok() const { return errors.empty(); }
};

// Reads STL (ASCII or binary), OBJ, PLY or OFF by the file's extension. Errors name the file.
[[nodiscard]] PolygonSoup read_polygon_soup_file(const std::string& path, std::vector<ImportError>& errors);

// Polygons given as point ids (a VTK surface's cells, vtk_centerlines.hpp): checked before any
// repair. Each polygon has 3 or more ids, each id names a point, every point is finite; a
// problem is one error naming the polygon (`file`, "polygon 12: point id 99 is not among the
// 40 points"), and at most kMaxSurfacePolygons polygons are taken.
inline constexpr std::size_t kMaxSurfacePolygons = 20'000'000;
[[nodiscard]] PolygonSoup polygon_soup_from_cells(const std::vector<glm::dvec3>& points,
                                                  const std::vector<std::vector<std::int64_t>>& polygons,
                                                  const std::string& file, std::vector<ImportError>& errors);

// Repairs, checks and skeletonises a surface already in memory (`file` names it in messages).
[[nodiscard]] SurfaceImport import_surface_soup(PolygonSoup soup, std::string_view file, const SurfaceOptions& options);

}  // namespace cathbox::vessel_import
