#pragma once
// 3D Slicer markups files (.mrk.json, schema markups-schema-v1.0.3): {"@schema": ...,
// "markups": [ {...}, ... ]}. Every markup of type "Curve" (or "ClosedCurve", closed into a
// loop) becomes one polyline:
//  - "controlPoints": [{"position": [x, y, z], "positionStatus": "defined", ...}, ...]; points
//    whose positionStatus is "undefined" or "preview" are skipped;
//  - the radius per control point from the measurement named "Radius" (case-insensitive; another
//    name with `radius_name`): {"name": "Radius", "controlPointValues": [r0, r1, ...]}, one
//    value per control point (Slicer's Extract Centerline and stEVE's neuro cases write this);
//  - "coordinateSystem": "LPS" (the default) or "RAS" (x and y negated to give LPS), so the
//    output is in LPS whatever the file used;
//  - "coordinateUnits": "mm" (default) or "um" (or a [code, scheme, meaning] triple).
// Other markup types (points, lines, planes, ROIs) are skipped and counted. The JSON itself is
// parsed by nlohmann-json; problems name the line (and for JSON syntax, the byte) where they are.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "vessel_import/import_error.hpp"
#include "vessel_import/network_builder.hpp"

namespace cathbox::vessel_import {

struct SlicerRead {
  std::vector<Polyline> curves;    // positions and radii in mm, LPS
  std::size_t skipped_markups = 0;  // not curves
  std::size_t skipped_points = 0;   // control points without a defined position
  std::string coordinate_system;    // as the (first) curve stated it
  std::vector<ImportError> errors;
  [[nodiscard]] bool ok() const { return errors.empty(); }
};

// `unit_override_mm` > 0 replaces the file's coordinateUnits (mm per file unit).
[[nodiscard]] SlicerRead parse_slicer_markups(std::string_view text, std::string_view file,
                                              std::string_view radius_name = "Radius",
                                              double unit_override_mm = 0.0);

}  // namespace cathbox::vessel_import
