#pragma once
// Centrelines from other tools into a vessel model (HCLM): VTK polydata (legacy .vtk, XML .vtp)
// as VMTK writes them, 3D Slicer curve markups (.mrk.json), SWC (.swc); and vessel surfaces
// (STL, OBJ, PLY, OFF: surface_import.hpp), whose centrelines are their skeleton. See the readers'
// headers for what each accepts; all go through network_builder (segments, junctions,
// orientation) and vessel::filter_radii (outliers), then vessel::validate_model.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vessel/bend_guard.hpp"
#include "vessel/radius_filter.hpp"
#include "vessel/vessel_model.hpp"
#include "vessel_import/import_error.hpp"
#include "vessel_import/network_builder.hpp"
#include "vessel_import/surface_import.hpp"

namespace cathbox::vessel_import {

enum class Format { kVtkLegacy, kVtkXml, kSlicerMarkups, kSwc, kSurface };

// "vtk", "vtp", "slicer" (or "mrk.json"), "swc", "surface" (or "stl", "obj", "ply", "off").
[[nodiscard]] std::optional<Format> format_from_name(std::string_view name);
// By the file name: .vtk, .vtp, .mrk.json (or .json), .swc, .stl/.obj/.ply/.off (case-insensitive).
[[nodiscard]] std::optional<Format> format_from_path(std::string_view path);
[[nodiscard]] const char* format_name(Format format);

// Millimetres per unit: "mm" 1, "cm" 10, "m" 1000, "um" 0.001.
[[nodiscard]] std::optional<double> unit_to_mm(std::string_view unit);

struct ImportOptions {
  std::optional<Format> format;     // by the file name when not given
  double unit_mm = 0.0;             // > 0: the coordinates' unit in mm; 0: the file's own (Slicer) or mm
  std::string radius_array;         // VTK point array / Slicer measurement; empty: the usual names
  bool filter_radii = true;         // vessel::filter_radii before writing
  bool keep_largest = false;        // a surface in several pieces: keep the largest (else refused)
  // Orientation (network_builder.hpp, Orient), in the input's coordinates and unit (a Slicer
  // file: LPS, mm unless unit_mm): the free end nearest `inlet` is the inlet; the blind segment
  // nearest `sac` is an aneurysm sac (refused without `inlet`: kSacNeedsInlet). Unset: the widest
  // free end is the inlet, no sac is named.
  std::optional<glm::dvec3> inlet;
  std::optional<glm::dvec3> sac;
};

struct ImportResult {
  vessel::VesselModel model;
  Format format = Format::kSwc;
  std::size_t polylines = 0;        // read from the file (curves, line cells or centrelines, SWC branches)
  NetworkStats network;
  vessel::RadiusFilterReport filter;
  bool filtered = false;
  vessel::BendGuardReport bends;    // bends tighter than the lumen rounded (vessel/bend_guard.hpp)
  SurfaceStats surface;             // a surface's repair and skeleton (Format::kSurface)
  vessel::SurfaceMesh lumen;        // the repaired, closed surface (Format::kSurface), each triangle
                                    // tagged with the segment whose centreline is nearest
  std::vector<std::string> notes;   // what else was done or skipped ("3 markups that are not curves skipped");
                                    // "WARNING: the surface cannot be built: ..." when the mesher would refuse it
  std::vector<ImportError> errors;  // the first is the one to show
  [[nodiscard]] bool ok() const { return errors.empty(); }

  // One line: segments, junctions, cycles, radius range, what was changed.
  [[nodiscard]] std::string summary() const;
};

[[nodiscard]] ImportResult import_centerlines(const std::string& path, const ImportOptions& options = {});

// The same from text already in memory (not VTK, which VTK reads from the file itself).
[[nodiscard]] ImportResult import_centerlines_text(std::string_view text, std::string_view file, Format format,
                                                   const ImportOptions& options = {});

}  // namespace cathbox::vessel_import
