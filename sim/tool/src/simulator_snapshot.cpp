// The simulator's read-out: inserted positions and the snapshot the views draw.
#include "tool/simulator.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::tool {
namespace {

// An expanded stent node is drawn at the cage's radius: its contact radius is the part of it
// its axis may not leave the lumen's by (kStentAxisPlay), the cage round it is wider (never
// wider than its expanded diameter).
void draw_expanded_stent(const Rod& rod, const StentRetriever& stent, ToolSnapshot& s) {
  const std::size_t m = s.positions_mm.size();
  const std::size_t n = rod.node_total();
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t k = n - m + i;
    const double cage_mm = std::min(rod.node_radius_mm(k) / (1.0 - kStentAxisPlay), 0.5 * stent.node_diameter_mm(k));
    s.radii_mm[i] = std::max(s.radii_mm[i], static_cast<float>(cage_mm));
  }
}

}  // namespace

void Simulator::inserted_positions(std::size_t tool, std::vector<glm::dvec3>& out) const {
  out.clear();
  const Rod& rod = rods_[tool];
  const std::size_t n = rod.node_total();
  const double tip = tip_depth_mm(tool);
  const double start = free_start_[tool];
  const bool inner = outer_of_[tool] < rods_.size();
  const std::size_t k0 = inner ? 0 : rod.first_node();
  for (std::size_t k = k0; k < n; ++k) {
    const double depth = tip - rod.node_from_tip_mm(k);
    if (depth < 0.0 && k + 1 < n && tip - rod.node_from_tip_mm(k + 1) <= 0.0) continue;
    if (inner && depth <= start) {
      out.push_back(path_point(tool, depth));
    } else {
      out.push_back(rod.positions()[k]);
    }
  }
}

void Simulator::fill_tool_snapshot(const Rod& rod, ToolSnapshot& s) const {
  const std::size_t m = s.positions_mm.size();
  s.tangents.resize(m);
  s.normals.resize(m);
  s.radii_mm.resize(m);
  const std::size_t n = rod.node_total();
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t k = n - m + i;  // the snapshot holds the distal-most m nodes
    glm::dvec3 tangent = i + 1 < m ? s.positions_mm[i + 1] - s.positions_mm[i]
                                   : (m > 1 ? s.positions_mm[i] - s.positions_mm[i - 1] : entry_.direction);
    const double len = glm::length(tangent);
    tangent = len > 1e-12 ? tangent / len : entry_.direction;
    s.tangents[i] = tangent;
    glm::dvec3 normal = rod.directors()[std::min(k, n - 2)];
    normal -= tangent * glm::dot(normal, tangent);
    const double nl = glm::length(normal);
    s.normals[i] = nl > 1e-9 ? normal / nl : normal;
    s.radii_mm[i] = static_cast<float>(rod.node_radius_mm(k));
  }
  s.tip = rod.tip();
  s.contacts.assign(rod.contacts().begin(), rod.contacts().end());
}

void Simulator::copy_snapshot(Snapshot& out) const {
  out.time_s = time_s_;
  out.step = steps_;
  out.active_tool = active_;
  out.tools.resize(rods_.size() + coil_views_.size());
  for (std::size_t t = 0; t < rods_.size(); ++t) {
    const Rod& rod = rods_[t];
    ToolSnapshot& s = out.tools[t];
    s.name = rod.spec().name;
    s.kind = rod.spec().kind;
    s.insertion_mm = insertion_[t];
    s.rotation_rad = rotation_[t];
    s.detached = false;
    inserted_positions(t, s.positions_mm);
    fill_tool_snapshot(rod, s);
    if (const StentRetriever* st = stent(t)) draw_expanded_stent(rod, *st, s);
    s.tip_segment = tip_segment_[t];
    s.hand_force_mN = hand_force_[t];
    s.hand_torque_mNmm = hand_torque_[t];
    s.force_law = force_law(t);
    s.balloon_pressure_atm = 0.0;
    s.balloon_diameter_mm = 0.0;
    if (const Balloon* b = balloon(t)) {
      s.balloon_pressure_atm = b->pressure_atm();
      s.balloon_diameter_mm = b->diameter_mm();
      if (b->pressure_atm() > 0.0) {
        const std::size_t m = s.positions_mm.size();
        const std::size_t n = rod.node_total();
        for (std::size_t i = 0; i < m; ++i) {
          const double from_tip = rod.node_from_tip_mm(n - m + i);
          const double lo = b->spec().from_tip_mm;
          if (from_tip >= lo && from_tip <= lo + b->spec().length_mm) {
            s.radii_mm[i] = std::max(s.radii_mm[i], static_cast<float>(0.5 * b->diameter_mm()));
          }
        }
      }
    }
  }
  // The released coils as their last finished solves left them (released_view: never waiting
  // for a solve left running by the step, released_overlap).
  for (std::size_t i = 0; i < coil_views_.size(); ++i) {
    const Rod& coil = coil_views_[i];
    ToolSnapshot& s = out.tools[rods_.size() + i];
    s.name = coil.spec().name;
    s.kind = ToolKind::kCoil;
    s.insertion_mm = 0.0;
    s.rotation_rad = 0.0;
    s.detached = true;
    s.positions_mm.assign(coil.positions().begin(), coil.positions().end());
    fill_tool_snapshot(coil, s);
    s.tip_segment = -1;
    s.hand_force_mN = 0.0;
    s.hand_torque_mNmm = 0.0;
    s.force_law = ForceLaw{};
    s.balloon_pressure_atm = 0.0;
    s.balloon_diameter_mm = 0.0;
  }
}

}  // namespace cathbox::tool
