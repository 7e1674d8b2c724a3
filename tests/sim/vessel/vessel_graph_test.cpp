#include "vessel/vessel_graph.hpp"

#include <algorithm>

#include <gtest/gtest.h>

#include "vessel/case_generator.hpp"
#include "vessel/hclm.hpp"

namespace cathbox::vessel {
namespace {

int ends_at(const Junction& j, bool at_end) {
  return static_cast<int>(std::count_if(j.ends.begin(), j.ends.end(), [&](const SegmentEnd& e) { return e.at_end == at_end; }));
}

TEST(VesselGraph, YBifurcationIsOneJunctionAndThreeFreeEnds) {
  const VesselGraph g(CaseGenerator::y_bifurcation());
  ASSERT_EQ(g.junctions().size(), 1u);
  EXPECT_EQ(g.junctions()[0].ends.size(), 3u);
  EXPECT_EQ(ends_at(g.junctions()[0], true), 1);  // the parent's last point
  EXPECT_EQ(g.free_ends().size(), 3u);
  EXPECT_EQ(g.cycle_count(), 0);
  EXPECT_EQ(g.component_count(), 1);
  EXPECT_EQ(g.surface_euler_characteristic(), 2);
  EXPECT_EQ(g.junction_of(0, true), 0);
  EXPECT_EQ(g.junction_of(0, false), -1);
}

TEST(VesselGraph, ConfluenceJoinsTwoParentsIntoOneChild) {
  const HclmReadResult r = read_hclm(
      "s 3\n"
      "g 1\nl left_vertebral\np 0\nc 1 3\nn 2\nv -5 0 0 1.8\nv 0 0 10 1.8\n"
      "g 2\nl right_vertebral\np 0\nc 1 3\nn 2\nv 5 0 0 1.8\nv 0 0 10 1.8\n"
      "g 3\nl basilar\np 2 1 2\nc 0\nn 2\nv 0 0 10 1.6\nv 0 0 40 1.6\n");
  ASSERT_TRUE(r.ok()) << r.errors.front().to_string();
  const VesselGraph g(r.model);
  ASSERT_EQ(g.junctions().size(), 1u);
  EXPECT_EQ(ends_at(g.junctions()[0], true), 2);
  EXPECT_EQ(ends_at(g.junctions()[0], false), 1);
  EXPECT_EQ(g.cycle_count(), 0);
  EXPECT_EQ(g.free_ends().size(), 3u);
}

TEST(VesselGraph, NeuroHasTheCircleOfWillisLoops) {
  const VesselModel model = CaseGenerator::neuro();
  const VesselGraph g(model);
  EXPECT_EQ(g.component_count(), 1);
  // Anterior loop (ICA-A1-AComm-A1-ICA over the arch), two posterior loops (ICA-PComm-P1-basilar
  // -vertebral-subclavian-arch) and the vertebrobasilar loop (both vertebrals into the basilar).
  EXPECT_EQ(g.cycle_count(), 4);
  EXPECT_EQ(g.surface_euler_characteristic(), -6);
  int confluences = 0;
  for (const Junction& j : g.junctions()) confluences += ends_at(j, true) >= 2 ? 1 : 0;
  EXPECT_EQ(confluences, 4);  // basilar, both P2s, right A2
}

TEST(VesselGraph, AneurysmCaseHasAFourWayJunction) {
  const VesselGraph g(CaseGenerator::neuro_aneurysm());
  const auto four = std::count_if(g.junctions().begin(), g.junctions().end(),
                                  [](const Junction& j) { return j.ends.size() == 4; });
  EXPECT_EQ(four, 1);
}

TEST(VesselGraph, RandomGraphsHaveTheRequestedCycles) {
  for (int cycles = 1; cycles <= 4; ++cycles) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const VesselModel model = CaseGenerator::random_graph(seed, cycles);
      ASSERT_TRUE(validate_model(model).empty()) << validate_model(model).front().to_string();
      const VesselGraph g(model);
      EXPECT_EQ(g.cycle_count(), cycles);
      EXPECT_EQ(g.component_count(), 1);
    }
  }
}

TEST(VesselGraph, DisconnectedModelsCountComponents) {
  VesselModel model = CaseGenerator::y_bifurcation();
  VesselModel other = CaseGenerator::y_bifurcation();
  for (Segment& s : other.segments) {
    s.id += 10;
    for (auto& p : s.parents) p += 10;
    for (auto& c : s.children) c += 10;
    for (auto& p : s.points) p.pos_mm.x += 100.0;
    model.segments.push_back(s);
  }
  const VesselGraph g(model);
  EXPECT_EQ(g.component_count(), 2);
  EXPECT_EQ(g.cycle_count(), 0);
  EXPECT_EQ(g.surface_euler_characteristic(), 4);
}

}  // namespace
}  // namespace cathbox::vessel
