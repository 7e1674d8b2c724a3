// Detaching a coil: the distal part of the tool becomes a free rod (no clamp, held by drag, the
// wall and other rods) with the nodes, frames and contacts it had; the tool keeps the proximal
// part, its tip now at the detachment node.
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "rod_node_contact.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {

// The detachment node: the station length_mm from the tip, with two nodes on either side of it.
std::size_t Rod::station_vertex(double length_mm) const {
  const std::size_t n = x_.size();
  std::size_t k0 = n;
  for (std::size_t k = 0; k < n; ++k) {
    if (std::abs(from_tip_[k] - length_mm) < 1e-9) k0 = k;
  }
  return k0 + 2 >= n || k0 < 2 ? n : k0;  // not a node, or too short to stand alone
}

bool Rod::soften_joint(double length_mm, double share) {
  const std::size_t k0 = station_vertex(length_mm);
  if (k0 >= x_.size()) return false;
  if (joint_ != k0) {
    joint_ = k0;
    joint_ei_ = ei_[k0];
    joint_gj_ = gj_[k0];
  }
  const double s = std::clamp(share, 0.0, 1.0);
  ei_[k0] = joint_ei_ * s;
  gj_[k0] = joint_gj_ * s;
  return true;
}

Rod Rod::split_distal(double length_mm) {
  Rod coil;
  const std::size_t k0 = station_vertex(length_mm);
  if (k0 >= x_.size()) return coil;
  copy_distal(coil, k0, length_mm);
  keep_proximal(k0, length_mm);
  return coil;
}

// The coil: nodes [k0, n) of this rod, with the distal length_mm of its sections.
void Rod::copy_distal(Rod& coil, std::size_t k0, double length_mm) const {
  const std::size_t n = x_.size();
  const auto tail = [&](const auto& v, std::size_t from) {
    using V = std::decay_t<decltype(v)>;
    return V(v.begin() + static_cast<std::ptrdiff_t>(from), v.end());
  };
  coil.spec_ = spec_;
  coil.spec_.name = spec_.name + " (detached)";
  coil.spec_.detach_mm = 0.0;
  coil.spec_.inside.clear();
  // The coil's sections: the distal length_mm of the tool's.
  std::vector<ToolSection> distal;
  double left = length_mm;
  for (auto it = spec_.sections.rbegin(); it != spec_.sections.rend() && left > 1e-9; ++it) {
    ToolSection part = *it;
    part.length_mm = std::min(part.length_mm, left);
    left -= part.length_mm;
    distal.insert(distal.begin(), part);
  }
  coil.spec_.sections = distal;
  coil.settings_ = settings_;
  coil.length_mm_ = length_mm;
  coil.free_ = true;
  coil.from_tip_ = tail(from_tip_, k0);
  coil.radius_ = tail(radius_, k0);
  coil.inner_radius_ = tail(inner_radius_, k0);
  coil.ei_ = tail(ei_, k0);
  coil.ei_extra_.assign(n - k0, 0.0);
  coil.gj_ = tail(gj_, k0);
  coil.voronoi_ = tail(voronoi_, k0);
  coil.drag_per_mm_ = tail(drag_per_mm_, k0);
  coil.kbar1_ = tail(kbar1_, k0);
  coil.kbar2_ = tail(kbar2_, k0);
  coil.kturn1_ = tail(kturn1_, k0);
  coil.kturn2_ = tail(kturn2_, k0);
  coil.x_ = tail(x_, k0);
  coil.x_start_ = coil.x_;
  coil.x_pred_ = coil.x_;
  coil.load_.assign(n - k0, glm::dvec3(0.0));
  coil.coupling_.assign(n - k0, glm::dvec3(0.0));
  coil.grip_anchor_.assign(n - k0, glm::dvec3(0.0));
  coil.grip_limit_.assign(n - k0, 0.0);
  coil.node_contacts_ = tail(node_contacts_, k0);
  coil.edge_planes_ = edge_planes_;
  coil.rest_ = tail(rest_, k0);
  coil.theta_ = tail(theta_, k0);
  coil.theta_start_ = coil.theta_;
  coil.ref_twist_ = tail(ref_twist_, k0);
  coil.t_ = tail(t_, k0);
  coil.d1_ = tail(d1_, k0);
  coil.m1_ = tail(m1_, k0);
  coil.m2_ = tail(m2_, k0);
  // The new ends: half an edge each, no bending at the end vertex.
  coil.voronoi_.front() = 0.5 * coil.rest_.front();
  coil.kbar1_.front() = coil.kbar2_.front() = coil.kturn1_.front() = coil.kturn2_.front() = 0.0;
  coil.insertion_mm_ = insertion_mm_;
  coil.rotation_rad_ = rotation_rad_;
  coil.entry_ = entry_;
  coil.dir_ = dir_;
  coil.first_ = 0;
  coil.first_free_ = 0;
  coil.size_scratch();
}

// This rod keeps nodes [0, k0]: its tip is now the detachment node.
void Rod::keep_proximal(std::size_t k0, double length_mm) {
  const std::size_t m = k0 + 1;
  const auto head = [&](auto& v, std::size_t count) { v.resize(count); };
  for (auto* v : {&from_tip_, &radius_, &inner_radius_, &ei_, &ei_extra_, &gj_, &voronoi_, &drag_per_mm_, &kbar1_, &kbar2_,
                  &kturn1_, &kturn2_}) head(*v, m);
  for (auto* v : {&x_, &x_start_, &x_pred_, &load_, &coupling_, &grip_anchor_}) head(*v, m);
  head(grip_limit_, m);
  head(node_contacts_, m);
  for (auto* v : {&rest_, &theta_, &theta_start_}) head(*v, m - 1);
  head(ref_twist_, m);
  for (auto* v : {&t_, &d1_, &m1_, &m2_}) head(*v, m - 1);
  for (double& d : from_tip_) d -= length_mm;
  voronoi_.back() = 0.5 * rest_.back();
  kbar1_.back() = kbar2_.back() = kturn1_.back() = kturn2_.back() = 0.0;
  insertion_mm_ = std::max(0.0, insertion_mm_ - length_mm);
  stepped_insertion_mm_ = std::max(0.0, stepped_insertion_mm_ - length_mm);
  length_mm_ -= length_mm;
  double left = length_mm;
  while (!spec_.sections.empty() && left > 1e-9) {
    ToolSection& last = spec_.sections.back();
    if (last.length_mm <= left + 1e-9) {
      left -= last.length_mm;
      spec_.sections.pop_back();
    } else {
      last.length_mm -= left;
      left = 0.0;
    }
  }
  spec_.detach_mm = 0.0;
  joint_ = static_cast<std::size_t>(-1);
  contacts_.clear();
  edge_contacts_.clear();
  update_window();
}

}  // namespace cathbox::tool
