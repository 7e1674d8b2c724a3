#include "vessel_import/importer.hpp"

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <limits>
#include <sstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "lumen_regions.hpp"
#include "vessel/control_mesh_builder.hpp"
#include "vessel/hclm.hpp"
#include "vessel/point_range.hpp"
#include "vessel/vessel_graph.hpp"
#include "vessel/vessel_mesher.hpp"
#include "vessel_import/slicer_markups_reader.hpp"
#include "vessel_import/swc_reader.hpp"
#include "vessel_import/vtk_centerlines.hpp"

namespace cathbox::vessel_import {
namespace {

// The network, the radius filter and the final check, shared by every format.
// The first point outside the body's range (vessel/point_range.hpp), named by its polyline.
[[nodiscard]] std::string first_point_out_of_range(const std::vector<Polyline>& polylines,
                                                   const std::vector<Branch>& branches) {
  const auto check = [](const Polyline& line) -> std::string {
    for (std::size_t j = 0; j < line.points.size(); ++j) {
      const vessel::CenterlinePoint& p = line.points[j];
      if (std::string problem = vessel::point_range_problem(p.pos_mm, p.radius_mm); !problem.empty()) {
        return line.where + ", point " + std::to_string(j) + ": " + problem;
      }
    }
    return {};
  };
  for (const Polyline& line : polylines) {
    if (std::string problem = check(line); !problem.empty()) return problem;
  }
  for (const Branch& branch : branches) {
    if (std::string problem = check(branch.line); !problem.empty()) return problem;
  }
  return {};
}

// `unit`: mm per input unit, for the orientation points.
void finish(std::vector<Polyline> polylines, std::vector<Branch> branches, std::string_view file,
            const ImportOptions& options, double unit, ImportResult& result) {
  if (std::string problem = first_point_out_of_range(polylines, branches); !problem.empty()) {
    result.errors.push_back({std::string(file), 0, 0, std::move(problem)});
    return;
  }
  Orient orient;
  if (options.inlet) orient.inlet_mm = *options.inlet * unit;
  if (options.sac) orient.sac_mm = *options.sac * unit;
  NetworkBuild built = branches.empty() ? build_network(polylines, orient) : build_network(branches, orient);
  if (!built.ok()) {
    result.errors.push_back({std::string(file), 0, 0, built.error});
    return;
  }
  result.model = std::move(built.model);
  result.network = built.stats;
  if (!built.oriented.empty()) result.notes.push_back(built.oriented);
  if (options.filter_radii) {
    result.filter = vessel::filter_radii(result.model);
    result.filtered = true;
    if (result.filter.unusable_segments > 0) {
      result.errors.push_back({std::string(file), 0, 0,
                               std::to_string(result.filter.unusable_segments) +
                                   " vessel(s) without a single positive radius"});
      return;
    }
  }
  if (const auto problems = vessel::validate_model(result.model, file); !problems.empty()) {
    std::string message = problems.front().message;
    if (!options.filter_radii && message.find("radius") != std::string::npos) message += " (the radius filter is off)";
    result.errors.push_back({std::string(file), 0, 0, "the imported network is not valid: " + message});
    return;
  }
  // The mesher sweeps a tube along the centreline: a bend tighter than the lumen folds its wall.
  // On a valid model only (positive radii); the points move between their neighbours, so it stays valid.
  result.bends = vessel::round_tight_bends(result.model);
  // A valid network may still have a junction the mesher cannot give room (branches a few degrees
  // apart and shorter than the ~10 radii they need to part, or overlapping): the control mesh
  // meshes it by its fallback and says which in a few milliseconds (the default options, without
  // subdivision); the summary passes it on.
  vessel::MeshOptions coarse;
  coarse.subdivision_level = 0;
  coarse.fit_junctions = false;
  const vessel::VesselSurface check = vessel::build_vessel_surface(result.model, coarse);
  if (!check.ok()) result.notes.push_back("WARNING: the surface cannot be built: " + check.error);
  else if (std::string fallback = vessel::fallback_summary(check.control); !fallback.empty()) {
    result.notes.push_back(std::move(fallback));
  }
}

[[nodiscard]] std::string read_text(const std::string& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  std::ostringstream buffer;
  if (ok) buffer << in.rdbuf();
  return buffer.str();
}

// A surface's unit when none is given: a file whose largest extent is under one unit is in metres
// (a body part is not under a millimetre), anything else in millimetres; the note says which.
[[nodiscard]] double surface_unit_mm(const PolygonSoup& soup, std::vector<std::string>& notes) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity());
  glm::dvec3 hi(-std::numeric_limits<double>::infinity());
  for (const glm::dvec3& p : soup.points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 size = hi - lo;
  const double extent = std::max({size.x, size.y, size.z});
  char note[128];
  const bool metres = extent > 0.0 && extent < 1.0;
  std::snprintf(note, sizeof note, "units taken as %s (largest extent %.3g; --units to say)", metres ? "m" : "mm", extent);
  notes.push_back(note);
  return metres ? 1000.0 : 1.0;
}

// A surface's polygons (read from STL/OBJ/PLY/OFF or a VTK surface) into the result.
[[nodiscard]] double cpu_seconds_since(std::clock_t start) {
  return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
}

ImportResult import_surface(PolygonSoup soup, const std::string& path, const ImportOptions& options, ImportResult result,
                            double read_seconds) {
  result.format = Format::kSurface;
  SurfaceOptions surface_options;
  surface_options.keep_largest = options.keep_largest;
  surface_options.unit_mm = options.unit_mm > 0.0 ? options.unit_mm : surface_unit_mm(soup, result.notes);
  SurfaceImport imported = import_surface_soup(std::move(soup), path, surface_options);
  if (!imported.ok()) {
    result.errors = std::move(imported.errors);
    return result;
  }
  result.surface = imported.stats;
  result.surface.seconds.read = read_seconds;
  result.lumen = std::move(imported.lumen);
  result.polylines = imported.branches.size();
  const std::clock_t start = std::clock();
  finish({}, std::move(imported.branches), path, options, surface_options.unit_mm, result);
  if (result.ok()) tag_lumen_regions(result.model, result.lumen);
  const SurfaceStats& st = result.surface;
  const SurfaceStats::Seconds& s = result.surface.seconds;
  result.surface.seconds.graph = cpu_seconds_since(start);
  char note[384];
  std::snprintf(note, sizeof note,
                "surface of %zu polygons: %zu duplicate points merged, %zu open ends capped, %zu pieces dropped, "
                "lumen %zu triangles, skeleton %zu points; CPU %.2f s (read %.2f, repair %.2f, check %.2f, flow %.2f, "
                "centring %.2f, network %.2f)",
                st.polygons_read, st.points_merged, st.open_ends.size(), st.components_dropped, st.triangles,
                st.skeleton_points, s.read + s.repair + s.check + s.flow + s.centre + s.graph, s.read, s.repair, s.check,
                s.flow, s.centre, s.graph);
  result.notes.insert(result.notes.begin(), note);
  return result;
}

}  // namespace

ImportResult import_centerlines_text(std::string_view text, std::string_view file, Format format,
                                     const ImportOptions& options) {
  ImportResult result;
  result.format = format;
  const double unit = options.unit_mm > 0.0 ? options.unit_mm : 1.0;
  if (format == Format::kSwc) {
    SwcRead read = parse_swc(text, file);
    if (!read.ok()) {
      result.errors = std::move(read.errors);
      return result;
    }
    SwcBranches branches = swc_branches(read.samples, unit);
    result.polylines = branches.branches.size();
    if (branches.lone_samples > 0) result.notes.push_back(std::to_string(branches.lone_samples) + " lone root samples skipped");
    if (branches.branches.empty()) {
      result.errors.push_back({std::string(file), 0, 0, "no branch: every sample is a lone root"});
      return result;
    }
    finish({}, std::move(branches.branches), file, options, unit, result);
    return result;
  }
  if (format == Format::kSlicerMarkups) {
    SlicerRead read = parse_slicer_markups(text, file, options.radius_array.empty() ? "Radius" : options.radius_array,
                                           options.unit_mm);
    if (!read.ok()) {
      result.errors = std::move(read.errors);
      return result;
    }
    result.polylines = read.curves.size();
    if (read.skipped_markups > 0) result.notes.push_back(std::to_string(read.skipped_markups) + " markups that are not curves skipped");
    if (read.skipped_points > 0) result.notes.push_back(std::to_string(read.skipped_points) + " undefined control points skipped");
    if (read.coordinate_system == "RAS") result.notes.push_back("RAS coordinates turned to LPS");
    finish(std::move(read.curves), {}, file, options, unit, result);
    return result;
  }
  result.errors.push_back({std::string(file), 0, 0, "VTK files are read from disk (import_centerlines)"});
  return result;
}

ImportResult import_centerlines(const std::string& path, const ImportOptions& options) {
  const std::optional<Format> format = options.format ? options.format : format_from_path(path);
  if (!format) {
    ImportResult result;
    result.errors.push_back({path, 0, 0, "unknown format (use .vtk, .vtp, .mrk.json, .swc, .stl, .obj, .ply or .off, or --format)"});
    return result;
  }
  if (*format == Format::kSurface) {
    ImportResult result;
    const std::clock_t start = std::clock();
    PolygonSoup soup = read_polygon_soup_file(path, result.errors);
    if (!result.ok()) return result;
    return import_surface(std::move(soup), path, options, std::move(result), cpu_seconds_since(start));
  }
  if (*format == Format::kVtkLegacy || *format == Format::kVtkXml) {
    ImportResult result;
    result.format = *format;
    const std::clock_t start = std::clock();
    VtkRead read = read_vtk_centerlines(path, options.radius_array, *format == Format::kVtkXml);
    if (!read.ok()) {
      result.errors = std::move(read.errors);
      return result;
    }
    if (!read.arrays.polygons.empty()) {  // a surface (no line cells)
      PolygonSoup soup = polygon_soup_from_cells(read.arrays.points, read.arrays.polygons, path, result.errors);
      if (!result.ok()) return result;
      result.notes.push_back(std::string(format_name(*format)) + " surface");
      return import_surface(std::move(soup), path, options, std::move(result), cpu_seconds_since(start));
    }
    PolylinesRead lines = centerline_polylines(read.arrays, path, options.unit_mm > 0.0 ? options.unit_mm : 1.0);
    if (!lines.ok()) {
      result.errors = std::move(lines.errors);
      return result;
    }
    result.polylines = lines.polylines.size();
    result.notes.push_back("radius from '" + read.arrays.radius_array + "'");
    if (lines.regrouped_tracts > 0) {
      result.notes.push_back(std::to_string(lines.regrouped_tracts) + " tracts (CenterlineIds, TractIds) rejoined into " +
                             std::to_string(lines.polylines.size()) + " centrelines");
    }
    finish(std::move(lines.polylines), {}, path, options, options.unit_mm > 0.0 ? options.unit_mm : 1.0, result);
    return result;
  }
  bool ok = false;
  const std::string text = read_text(path, ok);
  if (!ok) {
    ImportResult result;
    result.errors.push_back({path, 0, 0, "cannot open file"});
    return result;
  }
  return import_centerlines_text(text, path, *format, options);
}

}  // namespace cathbox::vessel_import
