#include "vessel/case_generator.hpp"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "case_network.hpp"
#include "neuro_case.hpp"

namespace cathbox::vessel {

using detail::Network;

std::vector<std::string> CaseGenerator::case_names() {
  return {"neuro", "neuro_aneurysm", "neuro_small_aneurysm", "neuro_stenosis", "y_bifurcation"};
}

VesselModel CaseGenerator::make_case(const std::string& name) {
  if (name == "neuro") return neuro();
  if (name == "neuro_aneurysm") return neuro_aneurysm();
  if (name == "neuro_small_aneurysm") return neuro_small_aneurysm();
  if (name == "neuro_stenosis") return neuro_stenosis();
  if (name == "y_bifurcation") return y_bifurcation();
  return {};
}

VesselModel CaseGenerator::neuro() { return detail::build_neuro({}, false); }
VesselModel CaseGenerator::neuro_aneurysm() {
  return detail::build_neuro({.aneurysm = AneurysmSite::kMcaBifurcation, .dome_mm = 6.4, .neck_mm = 2.4}, false);
}
// The dense coiling case's sac (cases/neuro_coiling_dense.case): a small aneurysm of the published
// shape, round, 4.0 mm across on a 1.8 mm neck, 3.79 mm deep (aspect ratio 2.1), its neck plane
// 2.5 mm out from the M1's end so the bifurcation (both M2 origins) lies behind it. Small (< 5 mm)
// ruptured aneurysms measured dome 3.9 +- 1.1 mm, neck 1.6 mm, aspect ratio 2.1 +- 0.6 (Dolati et
// al., Calgary, PMC4494560, 2015); 3-4 mm aneurysms are 46.8 % of UCAS Japan's 6,697 (NEJM 2012).
VesselModel CaseGenerator::neuro_small_aneurysm() {
  return detail::build_neuro({.aneurysm = AneurysmSite::kMcaBifurcation,
                              .dome_mm = 4.0,
                              .neck_mm = 1.8,
                              .sac_shape = SacShape::kRound,
                              .neck_offset_mm = 2.5},
                             false);
}
VesselModel CaseGenerator::neuro_stenosis() { return detail::build_neuro({}, true); }
VesselModel CaseGenerator::neuro_variant(const NeuroMorphology& morphology) { return detail::build_neuro(morphology, false); }

VesselModel CaseGenerator::y_bifurcation() {
  // A common-carotid-sized parent (r 3 mm, 60 mm) splitting symmetrically at 60 degrees into two
  // r 2.2 mm branches of 50 mm: the simplest steering task.
  Network net;
  const std::int32_t parent = net.add("parent", {{{0, 0, 0}, 3.0}, {{0, 0, 30}, 3.0}, {{0, 0, 60}, 3.0}}, {}, 400.0);
  const glm::dvec3 split = net.end(parent);
  const double a = 30.0 * std::numbers::pi / 180.0;
  net.add("left_branch", {{split, 2.2}, {split + 25.0 * glm::dvec3(std::sin(a), 0, std::cos(a)), 2.2},
                          {split + 50.0 * glm::dvec3(std::sin(a), 0, std::cos(a)), 2.2}},
          {parent}, 200.0);
  net.add("right_branch", {{split, 2.2}, {split + 25.0 * glm::dvec3(-std::sin(a), 0, std::cos(a)), 2.2},
                           {split + 50.0 * glm::dvec3(-std::sin(a), 0, std::cos(a)), 2.2}},
          {parent}, 200.0);
  return net.take();
}

VesselModel CaseGenerator::helix(double helix_radius_mm, double pitch_mm, double turns, double radius_mm, int points) {
  VesselModel model;
  Segment s;
  s.id = 1;
  s.name = "helix";
  for (int i = 0; i < points; ++i) {
    const double t = 2.0 * std::numbers::pi * turns * i / (points - 1);
    s.points.push_back({{helix_radius_mm * std::cos(t), helix_radius_mm * std::sin(t), pitch_mm * t / (2.0 * std::numbers::pi)},
                        radius_mm});
  }
  model.segments.push_back(std::move(s));
  return model;
}

}  // namespace cathbox::vessel
