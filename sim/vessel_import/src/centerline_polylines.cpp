// The VTK-free half of the VTK importer: line cells and their arrays to polylines.
#include <algorithm>
#include <cmath>
#include <map>

#include <glm/geometric.hpp>

#include "vessel_import/vtk_centerlines.hpp"

namespace cathbox::vessel_import {

PolylinesRead centerline_polylines(const PolylineArrays& a, const std::string& file, double scale_to_mm) {
  PolylinesRead out;
  const auto fail = [&](std::string message) { out.errors.push_back({file, 0, 0, std::move(message)}); };
  if (a.radius.size() != a.points.size()) {
    fail("radius array '" + a.radius_array + "' has " + std::to_string(a.radius.size()) + " values for " +
         std::to_string(a.points.size()) + " points");
    return out;
  }
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    if (!std::isfinite(a.points[i].x) || !std::isfinite(a.points[i].y) || !std::isfinite(a.points[i].z)) {
      fail("point " + std::to_string(i) + " is not finite");
      return out;
    }
  }
  for (std::size_t c = 0; c < a.lines.size(); ++c) {
    for (std::int64_t id : a.lines[c]) {
      if (id < 0 || static_cast<std::uint64_t>(id) >= a.points.size()) {
        fail("line cell " + std::to_string(c) + " uses point " + std::to_string(id) + " of " +
             std::to_string(a.points.size()));
        return out;
      }
    }
  }
  const bool tracts = !a.centerline_ids.empty() && !a.tract_ids.empty();
  if (tracts && (a.centerline_ids.size() != a.lines.size() || a.tract_ids.size() != a.lines.size())) {
    fail("CenterlineIds/TractIds have " + std::to_string(a.centerline_ids.size()) + "/" +
         std::to_string(a.tract_ids.size()) + " values for " + std::to_string(a.lines.size()) + " line cells");
    return out;
  }
  const auto point = [&](std::int64_t id) {
    const auto i = static_cast<std::size_t>(id);
    return vessel::CenterlinePoint{a.points[i] * scale_to_mm, a.radius[i] * scale_to_mm};
  };
  if (!tracts) {
    for (std::size_t c = 0; c < a.lines.size(); ++c) {
      Polyline line;
      line.where = "line cell " + std::to_string(c);
      line.name = "centerline " + std::to_string(c);
      for (std::int64_t id : a.lines[c]) line.points.push_back(point(id));
      out.polylines.push_back(std::move(line));
    }
    return out;
  }
  // Whole centrelines from their tracts: cells grouped by CenterlineIds, in TractIds order.
  std::map<std::int64_t, std::vector<std::size_t>> by_centerline;
  for (std::size_t c = 0; c < a.lines.size(); ++c) by_centerline[a.centerline_ids[c]].push_back(c);
  for (auto& [id, cells] : by_centerline) {
    std::stable_sort(cells.begin(), cells.end(), [&](std::size_t x, std::size_t y) { return a.tract_ids[x] < a.tract_ids[y]; });
    Polyline line;
    line.where = "centerline " + std::to_string(id);
    line.name = "centerline " + std::to_string(id);
    for (std::size_t c : cells) {
      for (std::int64_t pid : a.lines[c]) {
        const vessel::CenterlinePoint p = point(pid);
        // A tract starts where the previous one ended: that point once.
        if (!line.points.empty() && glm::length(p.pos_mm - line.points.back().pos_mm) == 0.0) continue;
        line.points.push_back(p);
      }
    }
    out.regrouped_tracts += cells.size();
    out.polylines.push_back(std::move(line));
  }
  return out;
}

}  // namespace cathbox::vessel_import
