// The released coils solved on a thread of their own beside the attached tools
// (Simulator::set_released_in_parallel, simulator_released.cpp): the same results, bit for bit,
// as solved on the calling thread at the same point, and as with the job left running past the
// step (Simulator::set_released_overlap); and each side reads the other where the step began.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tool/simulator.hpp"
#include "tool/snapshot.hpp"

#include "coil_test_support.hpp"

namespace cathbox::tool {
namespace {

using namespace testing;  // coil_test_support.hpp

constexpr std::size_t kFirst = 1, kSecond = 2;

std::vector<ToolSpec> micro_and_two_coils() {
  ToolSpec first = default_coil(kCoilLength, kLoopD), second = default_coil(kCoilLength, kLoopD);
  first.name = "coil 1";
  second.name = "coil 2";
  return {default_microcatheter(), first, second};
}

bool same_nodes(std::span<const glm::dvec3> a, std::span<const glm::dvec3> b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
}

// Both simulators pushed to the second coil's insertion x and stepped: every attached tool's
// nodes and the second coil's hand force the same, bit for bit.
void step_both_alike(Simulator& a, Simulator& b, double x, int step) {
  for (Simulator* s : {&a, &b}) {
    s->set_insertion(kSecond, x);
    s->step();
  }
  for (std::size_t t = 0; t < a.tool_count(); ++t) {
    ASSERT_TRUE(same_nodes(a.rod(t).positions(), b.rod(t).positions())) << "tool " << t << ", step " << step;
  }
  ASSERT_EQ(a.hand_force_mN(kSecond), b.hand_force_mN(kSecond)) << "step " << step;
}

// The first coil released in the sphere, its pusher drawn back, the second at the
// microcatheter's tip; returns the microcatheter's insertion.
double release_the_first(Simulator& s) {
  const double micro = place_microcatheter(s);
  drive(s, kSecond, micro - 20.0, 0.2);
  drive(s, kFirst, micro + kCoilLength + 1.0, 0.02);
  EXPECT_EQ(release_coil(s, kFirst), DeviceError::kNone);
  drive(s, kFirst, micro - 10.0, 0.2);
  drive(s, kSecond, micro - 0.5, 0.2);
  return micro;
}

// The first coil released in the sphere, the second pushed out against it: every node of every
// rod, and the hand force, equal at every step, threaded and not.
TEST(ReleasedInParallel, GivesTheSameStepsBitForBitAsSolvedOnTheCallingThread) {
  const TubeNetworkWall wall = sphere_on_a_tube();
  const std::vector<ToolSpec> tools = micro_and_two_coils();
  Simulator threaded(wall, tools, kEntry), inline_(wall, tools, kEntry);
  threaded.set_released_in_parallel(true);
  inline_.set_released_in_parallel(false);
  ASSERT_TRUE(threaded.released_in_parallel());
  ASSERT_FALSE(inline_.released_in_parallel());
  double micro = 0.0;
  for (Simulator* s : {&threaded, &inline_}) micro = release_the_first(*s);
  ASSERT_EQ(threaded.detached_count(), 1u);
  const std::vector<glm::dvec3> start(threaded.detached(0).positions().begin(), threaded.detached(0).positions().end());
  int steps = 0;
  for (double x = micro - 0.5; x < micro + 10.0; x += 0.02, ++steps) {
    ASSERT_NO_FATAL_FAILURE(step_both_alike(threaded, inline_, x, steps));
    ASSERT_TRUE(same_nodes(threaded.detached(0).positions(), inline_.detached(0).positions())) << "step " << steps;
  }
  // Not vacuous: the second coil's 10 mm pushed the released one about.
  double moved = 0.0;
  for (std::size_t k = 0; k < start.size(); ++k) moved = std::max(moved, glm::length(threaded.detached(0).positions()[k] - start[k]));
  EXPECT_GT(moved, 0.05) << "the released coil hardly moved";
}

// The same run with the released coil's job left running past each step (overlap): every
// attached tool's nodes and the hand force equal the job-joined run's at every step, without
// waiting for the job; what a tick reads of the coil after the step (released_view, the
// snapshot) is the coil as the last step left it, one step behind; settled (by detached(), or
// by the next step), the coil is the joined run's, bit for bit.
TEST(ReleasedInParallel, AJobLeftRunningPastTheStepGivesTheSameStepsAndIsReadAsTheStepBegan) {
  const TubeNetworkWall wall = sphere_on_a_tube();
  const std::vector<ToolSpec> tools = micro_and_two_coils();
  Simulator joined(wall, tools, kEntry), overlap(wall, tools, kEntry);
  joined.set_released_in_parallel(true);
  overlap.set_released_in_parallel(true);
  double micro = 0.0;
  for (Simulator* s : {&joined, &overlap}) micro = release_the_first(*s);
  overlap.set_released_overlap(true);
  ASSERT_TRUE(overlap.released_overlap());
  ASSERT_EQ(overlap.detached_count(), 1u);
  std::vector<glm::dvec3> last(joined.detached(0).positions().begin(), joined.detached(0).positions().end());
  Snapshot snap;
  int steps = 0, behind = 0;
  for (double x = micro - 0.5; x < micro + 5.0; x += 0.02, ++steps) {
    ASSERT_NO_FATAL_FAILURE(step_both_alike(joined, overlap, x, steps));
    // Read as the step began: the coil where the last step's job left it.
    ASSERT_TRUE(same_nodes(overlap.released_view(0).positions(), last)) << "step " << steps;
    overlap.copy_snapshot(snap);
    const ToolSnapshot& coil = snap.tools[overlap.tool_count()];
    ASSERT_TRUE(coil.detached);
    ASSERT_TRUE(same_nodes(coil.positions_mm, last)) << "step " << steps;
    behind += same_nodes(joined.detached(0).positions(), last) ? 0 : 1;
    last.assign(joined.detached(0).positions().begin(), joined.detached(0).positions().end());
    // Settled on one step in three (detached() waits for the job; on the others the next step
    // takes it in first): the joined run's coil.
    if (steps % 3 == 0) {
      ASSERT_TRUE(same_nodes(overlap.detached(0).positions(), last)) << "step " << steps;
      ASSERT_TRUE(same_nodes(overlap.released_view(0).positions(), last)) << "settled, step " << steps;
    }
  }
  // Not vacuous: on its turns the coil moved, and was read a step behind.
  EXPECT_GT(behind, steps / 4) << "of " << steps;
}

}  // namespace
}  // namespace cathbox::tool
