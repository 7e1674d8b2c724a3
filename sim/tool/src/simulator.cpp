#include "tool/simulator.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::tool {

namespace {
constexpr double kTipProbeRange_mm = 20.0;
}

Simulator::Simulator(const WallModel& wall, std::span<const ToolSpec> tools, const Entry& entry,
                     const RodSettings& settings)
    : wall_(wall), entry_(entry) {
  rods_.reserve(tools.size());
  std::size_t max_nodes = 0;
  for (const ToolSpec& spec : tools) {
    rods_.emplace_back(spec, settings);
    rods_.back().set_entry(entry.point_mm, entry.direction);
    max_nodes = std::max(max_nodes, rods_.back().node_total());
  }
  const std::size_t n = rods_.size();
  outer_of_.assign(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    if (tools[i].inside.empty()) continue;
    const std::size_t j = find_tool(tools[i].inside);
    if (j < n && j != i && tools[j].inside.empty()) outer_of_[i] = j;
  }
  for (std::size_t i = 0; i < n; ++i) if (outer_of_[i] == n) order_.push_back(i);
  for (std::size_t i = 0; i < n; ++i) if (outer_of_[i] != n) order_.push_back(i);
  insertion_.assign(n, 0.0);
  rotation_.assign(n, 0.0);
  stepped_insertion_.assign(n, 0.0);
  tip_segment_.assign(n, -1);
  tip_hint_.assign(n, WallHint{});
  extra_ei_.assign(max_nodes, 0.0);
}

std::size_t Simulator::find_tool(std::string_view name) const {
  for (std::size_t i = 0; i < rods_.size(); ++i) {
    if (rods_[i].spec().name == name) return i;
  }
  return rods_.size();
}

void Simulator::select(std::size_t tool) {
  if (tool < rods_.size()) active_ = tool;
}

void Simulator::set_insertion(std::size_t tool, double insertion_mm) {
  if (tool >= rods_.size() || !std::isfinite(insertion_mm)) return;
  insertion_[tool] = std::clamp(insertion_mm, 0.0, rods_[tool].max_insertion_mm());
}

void Simulator::set_rotation(std::size_t tool, double rotation_rad) {
  if (tool >= rods_.size() || !std::isfinite(rotation_rad)) return;
  rotation_[tool] = rotation_rad;
}

void Simulator::update_composite(std::size_t outer) {
  // Where an inner tool runs inside, the outer one bends with both stiffnesses.
  Rod& rod = rods_[outer];
  const std::size_t n = rod.node_total();
  std::fill(extra_ei_.begin(), extra_ei_.begin() + static_cast<std::ptrdiff_t>(n), 0.0);
  bool any = false;
  for (std::size_t t = 0; t < rods_.size(); ++t) {
    if (outer_of_[t] != outer) continue;
    any = true;
    const double inner_insertion = insertion_[t];
    for (std::size_t k = rod.first_node(); k < n; ++k) {
      const double depth = insertion_[outer] - rod.node_from_tip_mm(k);
      if (depth > 0.0 && depth <= inner_insertion) {
        extra_ei_[k] += rods_[t].bending_at_Nmm2(inner_insertion - depth);
      }
    }
    // A catheter advanced over the wire follows the wire's path.
    rod.set_leader(inner_insertion > insertion_[outer] ? &rods_[t] : nullptr, inner_insertion);
  }
  if (any) rod.set_extra_bending(std::span<const double>(extra_ei_.data(), n));
}

void Simulator::step_inner(std::size_t tool, double dt_s) {
  Rod& rod = rods_[tool];
  const std::size_t outer = outer_of_[tool];
  const Rod& out = rods_[outer];
  const double outer_insertion = insertion_[outer];
  if (outer_insertion > 0.0) {
    const TipPose tip = out.tip();
    rod.move_entry(tip.position_mm, tip.direction, out.reference_director(out.node_total() - 2));
  } else {
    rod.move_entry(entry_.point_mm, entry_.direction, glm::dvec3(0.0));
  }
  rod.set_material_advance(insertion_[tool] - stepped_insertion_[tool]);
  rod.set_boundary(std::max(0.0, insertion_[tool] - outer_insertion), rotation_[tool]);
  rod.step(dt_s, wall_);
}

void Simulator::step(double dt_s) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) dt_s = 1e-3;
  for (const std::size_t t : order_) {
    if (outer_of_[t] != rods_.size()) {
      step_inner(t, dt_s);
    } else {
      update_composite(t);
      rods_[t].set_boundary(insertion_[t], rotation_[t]);
      rods_[t].step(dt_s, wall_);
    }
    stepped_insertion_[t] = insertion_[t];
    WallProbe probe;
    probe.center_mm = rods_[t].tip().position_mm;
    probe.range_mm = kTipProbeRange_mm;
    WallContact c;
    if (insertion_[t] > 0.0 && wall_.probe(probe, tip_hint_[t], c)) tip_segment_[t] = c.segment;
    else if (insertion_[t] <= 0.0) tip_segment_[t] = -1;
  }
  time_s_ += dt_s;
  ++steps_;
}

double Simulator::hand_force_mN(std::size_t tool) const { return rods_[tool].hand_force_mN(); }
double Simulator::hand_torque_mNmm(std::size_t tool) const { return rods_[tool].hand_torque_mNmm(); }

ForceLaw Simulator::force_law(std::size_t tool) const {
  ForceLaw law = rods_[tool].force_law();
  // The inner tool's law is expressed in its own insertion, not its protrusion.
  law.insertion0_mm = insertion_[tool];
  return law;
}

void Simulator::inserted_positions(std::size_t tool, std::vector<glm::dvec3>& out) const {
  out.clear();
  const Rod& rod = rods_[tool];
  const std::size_t n = rod.node_total();
  const std::size_t outer = outer_of_[tool];
  const double outer_insertion = outer < rods_.size() ? insertion_[outer] : 0.0;
  const std::size_t k0 = outer < rods_.size() ? 0 : rod.first_node();
  for (std::size_t k = k0; k < n; ++k) {
    const double depth = insertion_[tool] - rod.node_from_tip_mm(k);
    if (depth < 0.0 && k + 1 < n && insertion_[tool] - rod.node_from_tip_mm(k + 1) <= 0.0) continue;
    if (outer < rods_.size() && depth <= outer_insertion) {
      out.push_back(depth <= 0.0 ? entry_.point_mm + entry_.direction * depth
                                 : rods_[outer].point_at_depth(depth, nullptr, nullptr));
    } else {
      out.push_back(rod.positions()[k]);
    }
  }
}

void Simulator::copy_snapshot(Snapshot& out) const {
  out.time_s = time_s_;
  out.step = steps_;
  out.active_tool = active_;
  out.tools.resize(rods_.size());
  for (std::size_t t = 0; t < rods_.size(); ++t) {
    const Rod& rod = rods_[t];
    ToolSnapshot& s = out.tools[t];
    s.name = rod.spec().name;
    s.kind = rod.spec().kind;
    s.insertion_mm = insertion_[t];
    s.rotation_rad = rotation_[t];
    inserted_positions(t, s.positions_mm);
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
    s.tip_segment = tip_segment_[t];
    s.contacts.assign(rod.contacts().begin(), rod.contacts().end());
    s.hand_force_mN = rod.hand_force_mN();
    s.hand_torque_mNmm = rod.hand_torque_mNmm();
    s.force_law = force_law(t);
  }
}

}  // namespace cathbox::tool
