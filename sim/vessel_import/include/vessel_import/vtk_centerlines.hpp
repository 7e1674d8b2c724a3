#pragma once
// Centrelines in VTK polydata, as VMTK writes them (vmtkcenterlines, vmtkbranchextractor,
// vmtknetworkextraction) in legacy .vtk or XML .vtp files: points, line cells (polylines),
// the radius as a point-data array (VMTK: "MaximumInscribedSphereRadius"; network extraction:
// "Radius"; DBiharMesher: "radii"), and after vmtkbranchextractor the cell-data arrays "CenterlineIds" and "TractIds"
// (each centreline cut into tracts at its branch points, the shared tracts repeated).
//
// read_vtk_centerlines() reads the file with VTK (vtkPolyDataReader, vtkXMLPolyDataReader) and
// copies what it needs into PolylineArrays; everything after that is ours and has no VTK in
// it (centerline_polylines(), fuzzed on its own). With CenterlineIds and TractIds present the
// tracts are put back together into whole centrelines (tracts of one centreline in TractIds
// order, the shared end point once), which network_builder then splits its own way.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel_import/import_error.hpp"
#include "vessel_import/network_builder.hpp"

namespace cathbox::vessel_import {

// What a polydata's lines hold, copied out of VTK.
struct PolylineArrays {
  std::vector<glm::dvec3> points;
  std::vector<double> radius;                      // one per point
  std::vector<std::vector<std::int64_t>> lines;    // point ids per line cell
  std::vector<std::int64_t> centerline_ids;        // per line cell, or empty
  std::vector<std::int64_t> tract_ids;             // per line cell, or empty
  std::string radius_array;                        // the array's name (for messages)
  // A surface instead (no line cells; e.g. the Vascular Model Repository's and Aneurisk's
  // model.vtp): point ids per polygon cell, triangle strips split into triangles. No radius.
  std::vector<std::vector<std::int64_t>> polygons;
};

struct PolylinesRead {
  std::vector<Polyline> polylines;
  std::size_t regrouped_tracts = 0;  // line cells put back into whole centrelines
  std::vector<ImportError> errors;
  [[nodiscard]] bool ok() const { return errors.empty(); }
};

// Checks ids and sizes and makes the polylines (positions and radii times `scale_to_mm`).
[[nodiscard]] PolylinesRead centerline_polylines(const PolylineArrays& arrays, const std::string& file,
                                                 double scale_to_mm);

// The default radius arrays, tried in this order when none is named.
[[nodiscard]] inline const std::vector<std::string>& default_radius_arrays() {
  static const std::vector<std::string> names = {"MaximumInscribedSphereRadius", "Radius", "radius", "radii"};
  return names;
}

struct VtkRead {
  PolylineArrays arrays;
  std::vector<ImportError> errors;
  [[nodiscard]] bool ok() const { return errors.empty(); }
};

// Reads a legacy .vtk (xml false) or XML .vtp (xml true) file with VTK, in the reader module
// libcathbox_vessel_import_vtk.so opened on first use (an error names it when it is missing).
// `radius_array` empty: the first of default_radius_arrays() present. A polydata without line
// cells but with polygons or triangle strips is a surface: its points and polygons come back
// (arrays.polygons non-empty) for surface_import.hpp.
[[nodiscard]] VtkRead read_vtk_centerlines(const std::string& path, const std::string& radius_array, bool xml);

}  // namespace cathbox::vessel_import
