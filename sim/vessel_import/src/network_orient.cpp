#include "network_orient.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::vessel_import {
namespace {

// The distance from p to a segment's centreline.
[[nodiscard]] double distance_to(const vessel::Segment& s, const glm::dvec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < s.points.size(); ++k) {
    const glm::dvec3 a = s.points[k].pos_mm;
    const glm::dvec3 d = s.points[k + 1].pos_mm - a;
    const double len2 = glm::dot(d, d);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, glm::length(p - (a + t * d)));
  }
  return best;
}

[[nodiscard]] std::string mm(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f mm", value);
  return text;
}

}  // namespace

std::string inlet_note(const vessel::VesselModel& model, const glm::dvec3& point_mm, double gap_mm) {
  std::size_t best = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < model.segments.size(); ++i) {
    const vessel::Segment& s = model.segments[i];
    const double d = s.parents.empty() ? glm::length(s.points.front().pos_mm - point_mm) : nearest;
    if (d < nearest) {
      nearest = d;
      best = i;
    }
  }
  return "inlet: segment " + std::to_string(model.segments[best].id) + "'s start, " + mm(gap_mm) + " from the point";
}

void name_sac(NetworkBuild& out, const glm::dvec3& point_mm) {
  std::vector<vessel::Segment>& segments = out.model.segments;
  std::size_t best = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const double d = distance_to(segments[i], point_mm);
    if (d < nearest) {
      nearest = d;
      best = i;
    }
  }
  vessel::Segment& sac = segments[best];
  const std::string which = "the segment nearest the point (" + std::to_string(sac.id) + ", " + mm(nearest) + " away)";
  if (!sac.children.empty()) {
    out.error = "--sac: " + which + " is not blind: it branches at its end";
    return;
  }
  if (sac.parents.empty()) {
    out.error = "--sac: " + which + " starts at an inlet (name an --inlet away from the sac)";
    return;
  }
  sac.name = kSacName;
  if (!out.oriented.empty()) out.oriented += "; ";
  out.oriented += "sac: segment " + std::to_string(sac.id) + " (" + mm(nearest) + " from the point) named '" + kSacName + "'";
}

}  // namespace cathbox::vessel_import
