// The trainee page's fluoroscopy made off the haptic tick (host/wasm fluoro_thread.hpp), compiled
// natively: the image the thread hands back is the one BrowserFluoro::frame makes on the caller's
// thread from the same snapshots, header and arrays alike, through the three images it rotates
// (each image's phantom and scenes copied only when their versions change) — a new pulse, a new
// C-arm pose (a new phantom), a new image size, and snapshots asked for again. No clock: the test
// asks again until the thread has made the image (a request may be skipped while it holds its lock).
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "wasm/browser_fluoro.hpp"
#include "wasm/fluoro_thread.hpp"

namespace cathbox::wasm {
namespace {

// A snapshot with the beam on at `pulse` (its scene version the pulse), one tool and its nodes at
// the pulse, the C-arm at `lao_deg`.
session::SceneSnapshot pulse_snapshot(std::int64_t pulse, double lao_deg) {
  session::SceneSnapshot s;
  s.sim_time_us = pulse * 66'667;
  s.tool_count = 1;
  s.tools[0].nodes_mm = {{0, 0, 100}, {0, 0, 110}, {0, 1, 120 + static_cast<float>(pulse)}};
  s.tools[0].radius_mm = 0.2F;
  s.fluoro.available = true;
  s.fluoro.pose.lao_deg = lao_deg;
  s.fluoro.image.pulse = pulse;
  s.fluoro.image.pulse_time_us = s.sim_time_us;
  s.fluoro.image.beam_on = true;
  s.fluoro.inputs_version = pulse;
  s.fluoro.pulse_tool_nodes_mm[0] = s.tools[0].nodes_mm;
  s.fluoro.pulse_tool_count = 1;
  return s;
}

void expect_same(const FluoroImage& got, const FluoroImage& want, int step) {
  EXPECT_EQ(got.header, want.header) << "step " << step;
  EXPECT_EQ(got.phantom, want.phantom) << "step " << step;
  EXPECT_EQ(got.scene_floats, want.scene_floats) << "step " << step;
  EXPECT_EQ(got.scene_indices, want.scene_indices) << "step " << step;
}

TEST(FluoroThread, HandsBackTheImageTheCallersThreadWouldMake) {
  const BrowserFluoro unopened;  // no lumen: the phantom and the tools' scenes
  FluoroThread thread(unopened);
  EXPECT_EQ(thread.take(), nullptr);  // nothing made yet
  BrowserFluoro reference = unopened;
  struct Step {
    std::int64_t pulse;
    double lao_deg;
    int width;
    int height;
  };
  const std::vector<Step> steps = {{3, 0, 64, 48}, {4, 0, 64, 48}, {4, 0, 64, 48}, {5, 30, 64, 48},
                                   {6, 30, 64, 48}, {6, 30, 80, 60}, {7, 30, 80, 60}, {7, 30, 80, 60}};
  double phantoms = 0;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Step& st = steps[i];
    const session::SceneSnapshot snap = pulse_snapshot(st.pulse, st.lao_deg);
    reference.frame(snap, st.width, st.height);
    const FluoroImage& want = reference.image();
    ASSERT_EQ(want.header[kHasImage], 1.0);
    const FluoroImage* got = nullptr;
    for (int tries = 0; tries < 1'000'000; ++tries) {
      thread.request(snap, st.width, st.height);
      got = thread.take();
      if (got != nullptr && got->header == want.header) break;
      std::this_thread::yield();
    }
    ASSERT_NE(got, nullptr);
    expect_same(*got, want, static_cast<int>(i));
    phantoms = want.header[kPhantomVersion];
  }
  EXPECT_EQ(phantoms, 3.0);  // AP, LAO 30, the larger image
  EXPECT_FALSE(reference.image().scene_indices.empty());
}

}  // namespace
}  // namespace cathbox::wasm
