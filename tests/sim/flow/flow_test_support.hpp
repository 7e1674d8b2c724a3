#pragma once
// Shared by the flow tests: bundled models, straight test vessels, and Kirchhoff's law checked
// from the vessel graph alone (independently of how the network numbers its nodes).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "flow/flow_network.hpp"
#include "scenario/case_file.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_graph.hpp"

namespace cathbox::flow::test {

inline std::string source_path(const std::string& relative) { return std::string(CATHBOX_SOURCE_DIR) + "/" + relative; }

inline vessel::VesselModel load_model(const std::string& relative) {
  vessel::HclmReadResult r = vessel::load_hclm(source_path(relative));
  EXPECT_TRUE(r.ok()) << relative;
  return r.model;
}

inline std::unique_ptr<FlowNetwork> build_or_fail(const vessel::VesselModel& model, const FlowSettings& settings = {}) {
  FlowBuild b = FlowNetwork::build(model, settings);
  EXPECT_TRUE(b) << (b ? "" : b.error().message);
  return b ? std::move(*b) : nullptr;
}

// A straight segment from `a` to `b` with constant radius, sampled every ~2 mm.
inline vessel::Segment straight(std::int32_t id, const glm::dvec3& a, const glm::dvec3& b, double r0, double r1 = -1.0) {
  vessel::Segment s;
  s.id = id;
  const int n = std::max(2, static_cast<int>(std::ceil(glm::length(b - a) / 2.0)) + 1);
  for (int i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / (n - 1);
    s.points.push_back({a + t * (b - a), r0 + t * ((r1 < 0.0 ? r0 : r1) - r0)});
  }
  return s;
}

inline void link(vessel::VesselModel& m, std::int32_t parent, std::int32_t child) {
  m.segments[*m.index_of(parent)].children.push_back(child);
  m.segments[*m.index_of(child)].parents.push_back(parent);
}

// A Y in the y-z plane: parent 1 along z from the origin to (0, 0, 60), branches 2 (+y) and 3 (-y)
// from its end to (0, +-spread, 60 + rise), each of constant radius.
inline vessel::VesselModel y_model(double parent_r, double left_r, double right_r, double spread_mm, double rise_mm) {
  vessel::VesselModel m;
  m.segments.push_back(straight(1, {0, 0, 0}, {0, 0, 60}, parent_r));
  m.segments.push_back(straight(2, {0, 0, 60}, {0, spread_mm, 60 + rise_mm}, left_r));
  m.segments.push_back(straight(3, {0, 0, 60}, {0, -spread_mm, 60 + rise_mm}, right_r));
  link(m, 1, 2);
  link(m, 1, 3);
  return m;
}

// Largest |sum of flows into a junction| over all junctions, relative to the largest flow.
inline double kirchhoff_residual(const FlowNetwork& net) {
  const vessel::VesselGraph graph(net.model());
  double largest = 0.0;
  for (const SegmentFlow& f : net.segments()) largest = std::max(largest, std::abs(f.flow_mm3_s));
  double worst = 0.0;
  for (const vessel::Junction& j : graph.junctions()) {
    double sum = 0.0;
    for (const vessel::SegmentEnd& e : j.ends) {
      const double q = net.segments()[e.segment].flow_mm3_s;
      sum += e.at_end ? q : -q;  // into the junction
    }
    worst = std::max(worst, std::abs(sum));
  }
  return largest > 0.0 ? worst / largest : worst;
}

}  // namespace cathbox::flow::test
