#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>

#include "vessel_import/importer.hpp"

namespace cathbox::vessel_import {

std::string ImportResult::summary() const {
  double r_min = std::numeric_limits<double>::infinity();
  double r_max = 0.0;
  for (const vessel::Segment& s : model.segments) {
    for (const vessel::CenterlinePoint& p : s.points) {
      r_min = std::min(r_min, p.radius_mm);
      r_max = std::max(r_max, p.radius_mm);
    }
  }
  char buf[512];
  std::snprintf(buf, sizeof buf, "%s, %zu polylines: %zu segments, %zu junctions, %zu free ends, %zu cycles, %zu components, radius %.3g..%.3g mm",
                format_name(format), polylines, model.segments.size(), network.junctions, network.free_ends,
                network.cycles, network.components, r_min, r_max);
  std::string out = buf;
  if (network.overlapping > 0) {
    out += "; " + std::to_string(network.overlapping) + " overlapping polylines split off a shared trunk (" +
           std::to_string(network.shared_points) + " shared points dropped)";
  }
  if (network.duplicates > 0) out += "; " + std::to_string(network.duplicates) + " duplicate polylines dropped";
  if (network.stubs > 0) {
    char stubs[112];
    std::snprintf(stubs, sizeof stubs, "; %zu free-ended stubs inside their junction's vessels pruned (up to %.3g mm)",
                  network.stubs, network.longest_stub_mm);
    out += stubs;
  }
  if (network.contracted > 0) out += "; " + std::to_string(network.contracted) + " short branches between junctions contracted";
  if (network.joined > 0) out += "; " + std::to_string(network.joined) + " pass-through nodes joined";
  if (network.ends_joined > 0) {
    char gap[96];
    std::snprintf(gap, sizeof gap, "; %zu curve ends joined to a nearby vessel across gaps up to %.3g mm",
                  network.ends_joined, network.widest_join_gap_mm);
    out += gap;
  }
  out += filtered ? "; radius filter " + filter.summary() : "; radius filter off";
  if (std::string rounded = bends.summary(); !rounded.empty()) out += "; " + rounded;
  for (const std::string& note : notes) out += "; " + note;
  return out;
}

}  // namespace cathbox::vessel_import
