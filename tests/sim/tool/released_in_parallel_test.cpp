// The released coils solved on a thread of their own beside the attached tools
// (Simulator::set_released_in_parallel, simulator_released.cpp): the same results, bit for bit,
// as solved on the calling thread at the same point; and each side reads the other where the
// step began.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tool/simulator.hpp"

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
  for (Simulator* s : {&threaded, &inline_}) {
    micro = place_microcatheter(*s);
    drive(*s, kSecond, micro - 20.0, 0.2);
    drive(*s, kFirst, micro + kCoilLength + 1.0, 0.02);
    ASSERT_EQ(release_coil(*s, kFirst), DeviceError::kNone);
    drive(*s, kFirst, micro - 10.0, 0.2);
    drive(*s, kSecond, micro - 0.5, 0.2);
  }
  ASSERT_EQ(threaded.detached_count(), 1u);
  const std::vector<glm::dvec3> start(threaded.detached(0).positions().begin(), threaded.detached(0).positions().end());
  int steps = 0;
  for (double x = micro - 0.5; x < micro + 10.0; x += 0.02, ++steps) {
    for (Simulator* s : {&threaded, &inline_}) {
      s->set_insertion(kSecond, x);
      s->step();
    }
    for (std::size_t t = 0; t < threaded.tool_count(); ++t) {
      ASSERT_TRUE(same_nodes(threaded.rod(t).positions(), inline_.rod(t).positions())) << "tool " << t << ", step " << steps;
    }
    ASSERT_TRUE(same_nodes(threaded.detached(0).positions(), inline_.detached(0).positions())) << "step " << steps;
    ASSERT_EQ(threaded.hand_force_mN(kSecond), inline_.hand_force_mN(kSecond)) << "step " << steps;
  }
  // Not vacuous: the second coil's 10 mm pushed the released one about.
  double moved = 0.0;
  for (std::size_t k = 0; k < start.size(); ++k) moved = std::max(moved, glm::length(threaded.detached(0).positions()[k] - start[k]));
  EXPECT_GT(moved, 0.05) << "the released coil hardly moved";
}

}  // namespace
}  // namespace cathbox::tool
