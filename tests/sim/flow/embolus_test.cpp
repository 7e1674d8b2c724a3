// Clot fragments carried by the flow: where they lodge, the grade they leave, and emboli to new
// territories.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "flow/embolus.hpp"
#include "flow_test_support.hpp"

namespace cathbox::flow {
namespace {

using test::build_or_fail;
using test::load_model;

std::uint32_t index_of(const vessel::VesselModel& m, std::int32_t id) { return static_cast<std::uint32_t>(*m.index_of(id)); }

// A fragment breaking off an M1 clot during retrieval, the M1 open again: it follows the flow
// into the M2 taking the most flow and lodges where the M2 narrows below its diameter; that M2's
// outlet is part of the target territory (no ENT), and the grade falls from 3 to 2b50 (one of
// two equal M2 territories reperfused: 50 %).
TEST(Embolus, FragmentFromTheM1LodgesInAnM2AndLowersTheGrade) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const std::vector<Terminal> open = net->terminals();
  const std::uint32_t m1 = index_of(model, 22);
  const Clot clot{m1, 2.0, 13.0, kReferenceComposition, 0.0};
  ASSERT_TRUE(net->occlude(std::vector<Clot>{clot}));
  const auto target = TargetTerritory::find(open, net->terminals());
  ASSERT_TRUE(target);
  ASSERT_TRUE(net->occlude({}));
  const auto path = carry_fragment(*net, Fragment{{m1, 10.0, 0.0}, 2.0, 3.0, kReferenceComposition});
  ASSERT_TRUE(path) << path.error().message;
  ASSERT_EQ(path->segments.size(), 2u);
  const std::string lodged_in = model.segments[path->lodged.segment].name;
  EXPECT_NE(lodged_in.find("left_middle_cerebral_m2"), std::string::npos) << lodged_in;
  EXPECT_FALSE(path->at_outlet);
  std::printf("2.0 mm fragment from the M1 lodges in %s at %.1f mm\n", lodged_in.c_str(), path->lodged.arc_start_mm + path->lodged.length_mm);
  const std::vector<Terminal> before = net->terminals();
  ASSERT_TRUE(net->occlude(std::vector<Clot>{path->lodged}));
  EXPECT_TRUE(new_territories(*target, before, net->terminals()).empty());
  EXPECT_NEAR(target->reperfused_fraction(net->terminals()), 0.5, 0.01);
  EXPECT_EQ(target->grade(net->terminals()), Etici::k2b50);
}

// A fragment breaking off at the carotid terminus while the M1 is still occluded goes where the
// flow goes, into the A1 and on into the A2: it starves the ACA, outside the target territory,
// an embolus to a new territory.
TEST(Embolus, FragmentIntoTheAcaIsAnEmbolusToANewTerritory) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const std::vector<Terminal> open = net->terminals();
  const Clot clot{index_of(model, 22), 2.0, 13.0, kReferenceComposition, 0.0};
  ASSERT_TRUE(net->occlude(std::vector<Clot>{clot}));
  const auto target = TargetTerritory::find(open, net->terminals());
  ASSERT_TRUE(target);
  const auto path = carry_fragment(*net, Fragment{{index_of(model, 21), 1.0, 0.0}, 1.8, 3.0, kReferenceComposition});
  ASSERT_TRUE(path) << path.error().message;
  const std::string lodged_in = model.segments[path->lodged.segment].name;
  EXPECT_NE(lodged_in.find("left_anterior_cerebral"), std::string::npos) << lodged_in;
  std::printf("1.8 mm fragment from the ICA terminus lodges in %s%s\n", lodged_in.c_str(), path->at_outlet ? " (at its outlet)" : "");
  const std::vector<Terminal> before = net->terminals();
  ASSERT_TRUE(net->occlude(std::vector<Clot>{clot, path->lodged}));
  const std::vector<std::size_t> ent = new_territories(*target, before, net->terminals());
  ASSERT_EQ(ent.size(), 1u);
  EXPECT_EQ(model.segments[open[ent[0]].segment].name, "left_anterior_cerebral_a2");
}

// A small fragment passes every vessel of the model and lodges at the end of an outlet.
TEST(Embolus, SmallFragmentLeavesThroughAnOutletAndBadFragmentsAreRefused) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const auto path = carry_fragment(*net, Fragment{{index_of(model, 20), 0.0, 0.0}, 0.5, 2.0, kReferenceComposition});
  ASSERT_TRUE(path);
  EXPECT_TRUE(path->at_outlet);
  EXPECT_GE(path->segments.size(), 3u);
  EXPECT_FALSE(carry_fragment(*net, Fragment{{9999, 0.0, 0.0}, 1.0, 2.0, kReferenceComposition}));
  EXPECT_FALSE(carry_fragment(*net, Fragment{{index_of(model, 20), 0.0, 0.0}, 0.0, 2.0, kReferenceComposition}));
  EXPECT_FALSE(carry_fragment(*net, Fragment{{index_of(model, 20), 0.0, 0.0}, 1.0, 2.0, {90.0, 20.0}}));
  // No flow: a sealed outlet branch.
  ASSERT_TRUE(net->occlude({}, std::vector<FlowArrest>{{index_of(model, 23)}}));
  const auto stuck = carry_fragment(*net, Fragment{{index_of(model, 23), 1.0, 0.0}, 1.0, 2.0, kReferenceComposition});
  ASSERT_FALSE(stuck);
  EXPECT_NE(stuck.error().message.find("no flow carries it"), std::string::npos);
}

}  // namespace
}  // namespace cathbox::flow
