// WallSwap's timing: the wall comes in at the tick the simulation decided, however early or
// late the worker builds it (a builder the test holds and releases, so the late path runs in
// virtual time: no sleeps, no wall-clock assertions), and the run is the same bit for bit.
#include "tool/wall_swap.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <functional>
#include <mutex>
#include <sstream>

#include "analytic_walls.hpp"
#include "state_fnv.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::tool {
namespace {

// A 100 mm wire, 0.36 mm, straight.
ToolSpec wire_100mm() {
  ToolSpec spec;
  spec.sections = {ToolSection{100.0, 0.36, 20.0, 15.0, 0.0}};
  return spec;
}

// A builder that waits until the test opens its gate (at most 20 s), then gives `make()`'s wall
// (a wider tube unless told).
struct GatedBuilder {
  std::mutex m;
  std::condition_variable cv;
  bool open = false;
  int built = 0;
  std::function<std::unique_ptr<WallModel>()> make = [] {
    return std::unique_ptr<WallModel>(std::make_unique<TubeNetworkWall>(testing::straight_tube(3.0, -10, 200)));
  };
  WallBuilder builder() {
    return [this](const vessel::VesselModel&) -> base::Result<std::unique_ptr<WallModel>> {
      std::unique_lock lock(m);
      cv.wait_for(lock, std::chrono::seconds(20), [&] { return open; });
      ++built;
      return make();
    };
  }
  void release() {
    {
      const std::lock_guard lock(m);
      open = true;
    }
    cv.notify_all();
  }
};

TEST(WallSwap, ALateBuildMakesTheDueTickWaitAndTheOldWallServesUntilIt) {
  GatedBuilder gate;
  auto first = std::make_unique<TubeNetworkWall>(testing::straight_tube(1.0, -10, 200));
  const WallModel* old = first.get();
  WallSwap swap(std::move(first), gate.builder(), WallSwap::Mode::kWorker, 300);
  int hook_calls = 0;
  swap.set_wait_hook([&] {  // the due tick found the builder held: let it finish now
    ++hook_calls;
    gate.release();
  });
  const std::vector<ToolSpec> tools{wire_100mm()};
  Simulator sim(swap.wall(), tools, Entry{{0, 0, 0}, {0, 0, 1}});
  ASSERT_TRUE(swap.request(vessel::VesselModel{}, 0));
  EXPECT_FALSE(swap.request(vessel::VesselModel{}, 0)) << "one wall at a time";
  WallHint hint;
  WallContact c;
  WallProbe probe;
  probe.center_mm = {0.5, 0, 50};
  probe.range_mm = 5.0;
  // Ticks 1..299 run on the old wall while the builder is held, and it still answers.
  for (int tick = 1; tick < 300; ++tick) {
    sim.set_insertion(0, 0.05 * tick);
    sim.step(1e-3);
    ASSERT_FALSE(swap.poll(sim, static_cast<std::int64_t>(sim.steps())));
  }
  EXPECT_EQ(&sim.wall(), old);
  ASSERT_TRUE(sim.wall().probe(probe, hint, c));
  EXPECT_NEAR(c.distance_mm, 0.5, 1e-9);
  EXPECT_EQ(hook_calls, 0);
  EXPECT_EQ(gate.built, 0);
  // Tick 300, the due tick: the builder is still held, so the tick waits for it and swaps.
  sim.set_insertion(0, 15.0);
  sim.step(1e-3);
  EXPECT_TRUE(swap.poll(sim, static_cast<std::int64_t>(sim.steps())));
  EXPECT_EQ(hook_calls, 1);
  EXPECT_EQ(gate.built, 1);
  EXPECT_EQ(swap.waits(), 1u);
  ASSERT_EQ(swap.wait_tally().recent_seconds().size(), 1u);
  EXPECT_EQ(swap.wait_tally().recent_seconds()[0], swap.wait_tally().max_seconds);
  EXPECT_NE(&sim.wall(), old);
  EXPECT_EQ(&sim.wall(), &swap.wall());
  ASSERT_TRUE(sim.wall().probe(probe, hint, c));
  EXPECT_NEAR(c.distance_mm, 2.5, 1e-9);
  EXPECT_EQ(swap.swaps(), 1u);
  EXPECT_EQ(sim.wall_swaps(), 1u);
}

// When a wall is built: in the request (kSynchronous); on the worker at once, a few ticks
// before the due tick, or only once the due tick waits for it.
enum class BuildTiming { kInTheRequest, kAtOnce, kShortlyBefore, kWhenTheDueTickWaits };

struct SwapRun {
  std::vector<std::uint64_t> hashes;  // per tick, chained
  std::int64_t swapped_at = -1;
  std::uint64_t waits = 0;
};

// A straight wire pushed at 0.05 mm a tick off-axis through a Y into its +x branch, whose wall
// the wire rides; at tick 600 a wider Y is asked for, due at 600 + latency.
SwapRun run_with_build(BuildTiming timing, std::int64_t latency = 300) {
  constexpr std::int64_t kRequestTick = 600, kTicks = 1400;
  GatedBuilder gate;
  gate.make = [] { return std::unique_ptr<WallModel>(std::make_unique<TubeNetworkWall>(testing::y_bifurcation(1.8, 1.5))); };
  if (timing == BuildTiming::kInTheRequest || timing == BuildTiming::kAtOnce) gate.release();
  const WallSwap::Mode mode = timing == BuildTiming::kInTheRequest ? WallSwap::Mode::kSynchronous : WallSwap::Mode::kWorker;
  WallSwap swap(std::make_unique<TubeNetworkWall>(testing::y_bifurcation()), gate.builder(), mode, latency);
  swap.set_wait_hook([&gate] { gate.release(); });
  const std::vector<ToolSpec> tools{wire_100mm()};
  Simulator sim(swap.wall(), tools, Entry{{0.3, 0, -40}, glm::normalize(glm::dvec3{0.03, 0, 1})});
  SwapRun run;
  std::uint64_t h = testing::kFnvBasis;
  for (std::int64_t tick = 1; tick <= kTicks; ++tick) {
    sim.set_insertion(0, 0.05 * static_cast<double>(tick));
    sim.step(1e-3);
    const auto now = static_cast<std::int64_t>(sim.steps());
    if (swap.poll(sim, now)) run.swapped_at = now;
    if (now == kRequestTick) {
      EXPECT_TRUE(swap.request(vessel::VesselModel{}, now));
      if (timing == BuildTiming::kAtOnce) swap.drain();
    }
    if (timing == BuildTiming::kShortlyBefore && now == kRequestTick + latency - 5) {
      gate.release();
      swap.drain();
    }
    h = testing::state_fnv(sim, h);
    run.hashes.push_back(h);
  }
  run.waits = swap.waits();
  swap.drain();
  return run;
}

// The tick a new wall comes in, and so the run, does not depend on when the builder finishes:
// built in the request, on the worker at once, a few ticks before it is due, or so late that
// the due tick waits for it, the swap comes at the due tick and every tick's positions and hand
// forces are the same bit for bit. The same wall one tick later changes them (the wire rides
// the wall that widens), so a swap that slipped by a tick would fail here.
TEST(WallSwap, TheRunIsTheSameBitForBitHoweverLateTheWorkerBuildsTheWall) {
  const SwapRun reference = run_with_build(BuildTiming::kInTheRequest);
  EXPECT_EQ(reference.swapped_at, 900);
  EXPECT_EQ(reference.waits, 0u);
  for (const BuildTiming timing : {BuildTiming::kAtOnce, BuildTiming::kShortlyBefore, BuildTiming::kWhenTheDueTickWaits}) {
    const SwapRun run = run_with_build(timing);
    const int k = static_cast<int>(timing);
    EXPECT_EQ(run.swapped_at, 900) << "timing " << k;
    EXPECT_EQ(run.waits, timing == BuildTiming::kWhenTheDueTickWaits ? 1u : 0u) << "timing " << k;
    ASSERT_EQ(run.hashes.size(), reference.hashes.size());
    const auto diff = std::mismatch(run.hashes.begin(), run.hashes.end(), reference.hashes.begin());
    EXPECT_EQ(diff.first, run.hashes.end()) << "timing " << k << ": first differs at tick " << (diff.first - run.hashes.begin()) + 1;
  }
  const SwapRun later = run_with_build(BuildTiming::kInTheRequest, 301);
  EXPECT_EQ(later.swapped_at, 901);
  // The wall swapped in after tick 900 first serves tick 901.
  EXPECT_EQ(later.hashes[900 - 1], reference.hashes[900 - 1]) << "the same run up to the swap";
  EXPECT_NE(later.hashes[901 - 1], reference.hashes[901 - 1]) << "a swap one tick later shows in the next tick's state";
  std::printf("end-state hash %016llx, the wall swapped in at tick %lld\n",
              static_cast<unsigned long long>(reference.hashes.back()), static_cast<long long>(reference.swapped_at));
}

// A balloon case's own first wall built on a surface meshed elsewhere (as the WebAssembly
// session, which cannot mesh, builds it on the case's surface) is the wall meshed here: the same
// model (the case's, unsmoothed: not the world's smoothed centrelines, whose lumen read split the
// trainee page's stent run from its native replay), the same contacts, the same lumen read.
TEST(BuildMeshWall, OnASurfaceMeshedElsewhereIsTheWallMeshedHere) {
  std::ifstream in(CATHBOX_SOURCE_DIR "/tests/host/session/data/stent_tube.hclm");
  std::ostringstream text;
  text << in.rdbuf();
  const vessel::HclmReadResult read = vessel::read_hclm(text.str(), "stent_tube.hclm");
  ASSERT_TRUE(read.ok());
  const auto here = build_mesh_wall(read.model);
  const auto given = build_mesh_wall(read.model, vessel::build_vessel_surface(read.model).mesh);
  ASSERT_TRUE(here) << here.error().message;
  ASSERT_TRUE(given) << given.error().message;
  EXPECT_EQ((*given)->surface()->model, read.model);
  EXPECT_EQ((*given)->surface()->model, (*here)->surface()->model);
  EXPECT_EQ((*given)->surface()->mesh.positions_mm, (*here)->surface()->mesh.positions_mm);
  int touched = 0;
  for (int i = 0; i < 400; ++i) {
    // Along the side branch (45 degrees from z = 30 mm) and round it.
    const double s = 0.05 * i;
    const glm::dvec3 p(0.7071 * s + 0.6 * std::cos(i), 0.6 * std::sin(i), 30.0 + 0.7071 * s);
    WallProbe probe;
    probe.center_mm = p;
    probe.radius_mm = 0.5;
    probe.lumen_axis = (i % 2) == 1;
    WallHint h1, h2;
    WallContact c1, c2;
    const bool a = (*here)->probe(probe, h1, c1);
    ASSERT_EQ((*given)->probe(probe, h2, c2), a) << i;
    touched += a ? 1 : 0;
    if (a) {
      EXPECT_EQ(c1.distance_mm, c2.distance_mm) << i;
      EXPECT_EQ(c1.normal, c2.normal) << i;
    }
    EXPECT_EQ((*given)->lumen_radius_mm(p), (*here)->lumen_radius_mm(p)) << i;
  }
  EXPECT_GT(touched, 100);
}

// The waits are tallied in fixed storage (the haptic thread never allocates for them): a count,
// a total and a maximum over every wait, and the last kRecent waits, oldest first, for a median.
TEST(WallSwapWaitTally, KeepsEveryWaitsSumAndMaximumAndTheLastOnesInOrder) {
  WallSwap::WaitTally tally;
  EXPECT_TRUE(tally.recent_seconds().empty());
  const std::size_t n = WallSwap::WaitTally::kRecent + 5;
  double total = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double w = k == 3 ? 9.0 : 1e-3 * static_cast<double>(k);  // the largest falls out of the ring
    tally.add(w);
    total += w;
  }
  EXPECT_EQ(tally.count, n);
  EXPECT_DOUBLE_EQ(tally.total_seconds, total);
  EXPECT_EQ(tally.max_seconds, 9.0);
  const std::vector<double> recent = tally.recent_seconds();
  ASSERT_EQ(recent.size(), WallSwap::WaitTally::kRecent);
  for (std::size_t i = 0; i < recent.size(); ++i) EXPECT_EQ(recent[i], 1e-3 * static_cast<double>(i + 5)) << i;
}

}  // namespace
}  // namespace cathbox::tool
