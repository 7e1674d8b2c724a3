// Two boxes on one rig (issue 16): the left box holds the catheter, the right box the
// guidewire. Two emulated boxes in-process on their own sockets and one virtual clock; the
// session runs tick by tick in virtual time. Each box moves only its own tool, whichever tool
// the UI calls held, and both render the force laws the session sends them.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "emu_world.hpp"
#include "session/multi_box_hand.hpp"
#include "session/session.hpp"

namespace cathbox::testing {
namespace {

// The tools' commanded insertions after each tick.
struct Insertions final : session::TickObserver {
  std::array<std::int64_t, session::kMaxTools> um{};
  void observe(const session::TickView& v) override {
    for (std::size_t t = 0; t < v.input.tool_count; ++t) um[t] = v.input.tools[t].insertion_um;
  }
};

std::unique_ptr<session::BoxHand> bound_box(EmuWorld& world, std::size_t box, std::size_t tool) {
  session::BoxHandOptions o;
  o.tool = tool;
  auto hand = session::BoxHand::attach(world.connect(box), o);
  if (!hand) throw std::runtime_error(hand.error().message);
  return std::move(*hand);
}

class TwoBoxes : public ::testing::Test {
 protected:
  void SetUp() override {
    emu::EmuOptions left;
    left.serial = "EMU-LEFT";
    emu::EmuOptions right;
    right.serial = "EMU-RIGHT";
    world = std::make_unique<EmuWorld>(std::vector<emu::EmuOptions>{left, right});
    session::SessionCaseLoad scene = session::load_session_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.case");
    ASSERT_TRUE(scene) << scene.error().message;
    ASSERT_EQ(scene.value()->spec.tools.size(), 2u);
    std::vector<session::MultiBoxHand::Bound> boxes;
    boxes.push_back({bound_box(*world, 0, 0), "catheter"});
    boxes.push_back({bound_box(*world, 1, 1), "guidewire"});
    auto hand = session::MultiBoxHand::make(std::move(boxes), 2);
    ASSERT_TRUE(hand) << hand.error().message;
    rig = hand->get();
    s = std::make_unique<session::Session>(std::move(scene.value()), std::move(*hand));
    s->add_observer(seen);
  }
  // Runs the boxes and the session tick by tick for `ms`.
  void run(int ms) {
    for (int i = 0; i < ms; ++i) {
      world->advance(1000);
      s->step_virtual(1);
    }
  }
  std::unique_ptr<EmuWorld> world;
  session::MultiBoxHand* rig = nullptr;
  std::unique_ptr<session::Session> s;
  Insertions seen;
};

TEST_F(TwoBoxes, EachBoxMovesItsOwnToolWhicheverIsHeld) {
  EXPECT_NE(rig->describe().find("catheter <- "), std::string::npos) << rig->describe();
  EXPECT_NE(rig->describe().find("guidewire <- "), std::string::npos) << rig->describe();
  ASSERT_TRUE(rig->device());
  EXPECT_EQ(rig->device()->serial, "EMU-LEFT");
  run(100);
  const auto start = seen.um;
  // The left hand pushes the catheter in 20 mm; the right hand stays.
  world->emu(0).set_hand(0, emu::HandScript::parse("v:20mm/s:1s").value());
  run(1500);
  EXPECT_NEAR(static_cast<double>(seen.um[0] - start[0]) * 1e-3, 20.0, 1.5);
  EXPECT_EQ(seen.um[1], start[1]);
  // The UI takes the other tool in hand: the boxes keep theirs. The right hand pushes 10 mm.
  ASSERT_TRUE(s->post(session::Control::select_tool(1)));
  const auto mid = seen.um;
  world->emu(1).set_hand(0, emu::HandScript::parse("v:10mm/s:1s").value());
  run(1500);
  EXPECT_EQ(seen.um[0], mid[0]);
  EXPECT_NEAR(static_cast<double>(seen.um[1] - mid[1]) * 1e-3, 10.0, 1.0);
  // Both boxes render force laws: each applied the session's commands.
  for (std::size_t b = 0; b < 2; ++b) {
    const cbx_state_report st = world->emu(b).core_state();
    EXPECT_GT(st.command_seq_echo, 1000u) << "box " << b;
    EXPECT_EQ(st.faults, 0u) << "box " << b;
  }
}

TEST(TwoBoxesSetup, BadBindingsGiveOneLine) {
  EmuWorld world(std::vector<emu::EmuOptions>{{}, {}});
  // One box is "tool in hand", not a rig of boxes.
  std::vector<session::MultiBoxHand::Bound> one;
  one.push_back({bound_box(world, 0, 0), "catheter"});
  const auto alone = session::MultiBoxHand::make(std::move(one), 2);
  ASSERT_FALSE(alone);
  EXPECT_NE(alone.error().message.find("two boxes"), std::string::npos) << alone.error().message;
  // Two boxes on one tool.
  std::vector<session::MultiBoxHand::Bound> same;
  same.push_back({bound_box(world, 0, 1), "guidewire"});
  same.push_back({bound_box(world, 1, 1), "guidewire"});
  const auto doubled = session::MultiBoxHand::make(std::move(same), 2);
  ASSERT_FALSE(doubled);
  EXPECT_EQ(doubled.error().message, "two boxes drive 'guidewire'");
  // A tool the case does not have.
  std::vector<session::MultiBoxHand::Bound> beyond;
  beyond.push_back({bound_box(world, 0, 0), "catheter"});
  beyond.push_back({bound_box(world, 1, 3), "coil"});
  const auto missing = session::MultiBoxHand::make(std::move(beyond), 2);
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().message, "box for 'coil': the case has 2 tools");
}

}  // namespace
}  // namespace cathbox::testing
