// The C-arm panel's model (no GL): each edit gives the session control the panel posts, the
// values out of range give none and one line naming the field, and the injection the I key
// and the Inject button use.
#include <gtest/gtest.h>

#include "app/carm_panel_model.hpp"
#include "session/control.hpp"

namespace cathbox::app {
namespace {

namespace fc = session::fluoro_control;
using session::ControlKind;

TEST(CArmPanelModel, AnglesGiveOneCArmAnglesControlAndOutOfRangeNone) {
  CArmPanelModel m;
  m.sync(flow::CArmPose{}, 15.0);
  const auto c = m.set_angles(30.0, -10.0);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, static_cast<std::uint16_t>(ControlKind::kCArmAngles));
  EXPECT_EQ(fc::read_angles(*c)->lao_deg, 30.0);
  EXPECT_EQ(fc::read_angles(*c)->cranial_deg, -10.0);
  EXPECT_EQ(m.pose().lao_deg, 30.0);
  EXPECT_FALSE(m.set_angles(30.0, -10.0)) << "unchanged: nothing to post";
  EXPECT_TRUE(m.error().empty());
  EXPECT_FALSE(m.set_angles(30.0, 75.0));
  EXPECT_EQ(m.error(), "C-arm: cranial/caudal angle must be within +-60 degrees");
  EXPECT_EQ(m.pose().cranial_deg, -10.0) << "a refused edit leaves the field";
}

TEST(CArmPanelModel, GeometryGivesOneCArmGeometryControl) {
  CArmPanelModel m;
  m.sync(flow::CArmPose{}, 15.0);
  const auto c = m.set_geometry(1100.0, -30.0, 320.0, 0.6);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, static_cast<std::uint16_t>(ControlKind::kCArmGeometry));
  const auto g = fc::read_geometry(*c);
  ASSERT_TRUE(g);
  EXPECT_EQ(g->sid_mm, 1100.0);
  EXPECT_EQ(g->table_height_mm, -30.0);
  EXPECT_EQ(g->fov_mm, 320.0);
  EXPECT_EQ(g->collimation, 0.6);
  EXPECT_FALSE(m.set_geometry(1500.0, -30.0, 320.0, 0.6));
  EXPECT_EQ(m.error(), "C-arm: source to image distance must be in [800, 1300] mm");
}

TEST(CArmPanelModel, PulseRatesAreTheUnitsThree) {
  CArmPanelModel m;
  m.sync(flow::CArmPose{}, 15.0);
  EXPECT_FALSE(m.set_pulse_rate(15.0));
  const auto c = m.set_pulse_rate(7.5);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, static_cast<std::uint16_t>(ControlKind::kPulseRate));
  EXPECT_EQ(fc::read_pulse_rate(*c), 7.5);
  EXPECT_FALSE(m.set_pulse_rate(10.0));
  EXPECT_EQ(m.error(), "pulse rate: 10 per s is not 7.5, 15 or 30");
  // The unit's rate (the snapshot) shows again after sync.
  m.sync(flow::CArmPose{}, 30.0);
  EXPECT_EQ(m.pulse_rate_hz(), 30.0);
}

TEST(CArmPanelModel, ProjectionsAreTheStandardOnesThenTheCasesWorkingViews) {
  const CArmPanelModel m({{"working AP cranial", 5.0, 25.0}});
  const std::vector<flow::NamedProjection> standard = flow::standard_projections();
  ASSERT_EQ(m.projections().size(), standard.size() + 1);
  EXPECT_EQ(m.projections().front().name, "AP");
  EXPECT_EQ(m.projections().back().name, "case: working AP cranial");
  CArmPanelModel edit({{"working", 5.0, 25.0}});
  edit.sync(flow::CArmPose{}, 15.0);
  const auto c = edit.pick_projection(standard.size());
  ASSERT_TRUE(c);
  EXPECT_EQ(fc::read_angles(*c)->lao_deg, 5.0);
  EXPECT_EQ(fc::read_angles(*c)->cranial_deg, 25.0);
  // The lateral is LAO 90.
  std::size_t lateral = standard.size();
  for (std::size_t i = 0; i < standard.size(); ++i) {
    if (standard[i].lao_deg == 90.0 && standard[i].cranial_deg == 0.0) lateral = i;
  }
  ASSERT_LT(lateral, standard.size());
  EXPECT_EQ(fc::read_angles(*edit.pick_projection(lateral))->lao_deg, 90.0);
  EXPECT_FALSE(edit.pick_projection(99));
  EXPECT_EQ(edit.error(), "projection 99: there are " + std::to_string(standard.size() + 1));
}

TEST(CArmPanelModel, TheInjectionSettingsGoIntoTheInjectControl) {
  CArmPanelModel m;
  // Default: 6 mL at 3 mL/s of 300 mgI/mL, the 16-byte payload the I key always sent.
  EXPECT_EQ(m.inject().size, 16);
  EXPECT_EQ(fc::read_inject(m.inject())->volume_ml, 6.0);
  ASSERT_TRUE(m.set_injection({8.0, 4.0, 350.0}));
  const auto p = fc::read_inject(m.inject());
  ASSERT_TRUE(p);
  EXPECT_EQ(p->volume_ml, 8.0);
  EXPECT_EQ(p->rate_ml_s, 4.0);
  EXPECT_EQ(p->concentration_mgI_ml, 350.0);
  EXPECT_FALSE(m.set_injection({8.0, 40.0, 350.0}));
  EXPECT_EQ(m.error(), "injection rate: 40 mL/s, must be in [0.5, 10]");
  EXPECT_FALSE(m.set_injection({0.0, 4.0, 350.0}));
  EXPECT_EQ(m.error(), "injection volume: 0 mL, must be in [1, 20]");
  EXPECT_FALSE(m.set_injection({8.0, 4.0, 500.0}));
  EXPECT_EQ(m.error(), "injection concentration: 500 mgI/mL, must be in [140, 350]");
  EXPECT_EQ(fc::read_inject(m.inject())->rate_ml_s, 4.0) << "refused settings keep the last good ones";
  EXPECT_EQ(CArmPanelModel::capture_roadmap().kind, static_cast<std::uint16_t>(ControlKind::kRoadmap));
  EXPECT_EQ(fc::read_flag(CArmPanelModel::capture_roadmap()), true);
  EXPECT_EQ(fc::read_flag(CArmPanelModel::clear_roadmap()), false);
}

}  // namespace
}  // namespace cathbox::app
