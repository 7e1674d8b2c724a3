// The stent retriever's U (unsheathe) and E (retrieve) drives of the keyboard hand (no GL;
// host/app/device_drive.hpp): what they select and the speed they set from snapshots built by
// hand (guide 0 > microcatheter 1 > stent 2, as in tests/host/session/stent_tube_case.hpp), and
// where they stop. The same keys in the trainer are driven by the browser test
// (tests/browser/train_stent.py, test_stent_keys).
#include <gtest/gtest.h>

#include "app/device_drive.hpp"

namespace cathbox::app {
namespace {

constexpr std::size_t kGuide = 0;
constexpr std::size_t kMicro = 1;
constexpr std::size_t kStent = 2;

session::SceneSnapshot stack(std::size_t held, double insertion_mm, float unsheathed_mm, bool retrieving = false) {
  session::SceneSnapshot s;
  s.tool_count = 3;
  s.held_tool = held;
  s.insertion_mm = insertion_mm;
  s.tools[kMicro].stent_carrier = -1;
  s.tools[kStent].stent_length_mm = 20.0F;
  s.tools[kStent].stent_carrier = static_cast<int>(kMicro);
  s.tools[kStent].stent_unsheathed_mm = unsheathed_mm;
  s.tools[kStent].stent_retrieving = retrieving;
  return s;
}

const DriveKeys kNone{};
const DriveKeys kU{true, false, false};
const DriveKeys kE{false, true, false};
const DriveKeys kArrow{false, false, true};
const DriveKeys kBox{false, false, false, true};  // a box holds the hand, no key
const DriveKeys kUBox{true, false, false, true};
const DriveKeys kEBox{false, true, false, true};

TEST(DeviceDrive, FindsTheStentInACatheter) {
  EXPECT_EQ(DeviceDrive::stent_tool(stack(kStent, 50.0, 0.0F)), static_cast<int>(kStent));
  session::SceneSnapshot bare = stack(kStent, 50.0, 0.0F);
  bare.tools[kStent].stent_carrier = -1;  // a stent in the vessel: nothing to unsheathe it from
  EXPECT_EQ(DeviceDrive::stent_tool(bare), -1);
  DeviceDrive d;
  const DriveCommand c = d.update(kU, bare);
  EXPECT_FALSE(c.driving);
  EXPECT_EQ(c.note, "U: no stent retriever in a catheter in this case");
  EXPECT_TRUE(d.hints(bare, {}).empty());
}

TEST(DeviceDrive, UnsheatheSelectsTheCarrierDrawsItBackAndStopsWhenTheStentIsOut) {
  DeviceDrive d;
  DriveCommand c = d.update(kU, stack(kStent, 50.0, 0.0F));
  EXPECT_TRUE(c.driving);
  ASSERT_TRUE(c.select);
  EXPECT_EQ(*c.select, kMicro) << "the microcatheter, not the push wire, is drawn back";
  EXPECT_EQ(c.insert_mm_s, 0.0) << "nothing moves until the select is applied";
  c = d.update(kNone, stack(kStent, 50.0, 0.0F));
  EXPECT_TRUE(c.driving);
  EXPECT_FALSE(c.select) << "posted once";
  EXPECT_EQ(c.insert_mm_s, 0.0);
  c = d.update(kNone, stack(kMicro, 56.0, 8.0F));
  EXPECT_TRUE(c.driving);
  EXPECT_EQ(c.insert_mm_s, -DeviceDrive::kUnsheathe_mm_s);
  EXPECT_EQ(c.insert_mm_s, -5.0);
  EXPECT_EQ(d.mode(), DeviceDrive::Mode::kUnsheathe);
  EXPECT_EQ(d.hints(stack(kMicro, 56.0, 8.0F), {"guide", "microcatheter", "stent"}).front(),
            "U: UNSHEATHING 8 / 20 mm, the microcatheter back at 5 mm/s (U, arrows or Tab: stop)");
  c = d.update(kNone, stack(kMicro, 44.0, 19.9F));
  EXPECT_EQ(c.insert_mm_s, -5.0) << "19.9 of 20 mm: not out yet";
  c = d.update(kNone, stack(kMicro, 43.5, 20.0F));
  EXPECT_FALSE(c.driving) << "fully unsheathed: it stops by itself";
  EXPECT_EQ(c.note, "U: the stent is unsheathed (20 / 20 mm)");
  EXPECT_EQ(d.mode(), DeviceDrive::Mode::kIdle);
  c = d.update(kU, stack(kMicro, 43.5, 20.0F));
  EXPECT_FALSE(c.driving);
  EXPECT_EQ(c.note, "U: the stent is already unsheathed");
}

TEST(DeviceDrive, UnsheatheWithTheCarrierHeldSelectsNothing) {
  DeviceDrive d;
  const DriveCommand c = d.update(kU, stack(kMicro, 56.0, 0.0F));
  EXPECT_TRUE(c.driving);
  EXPECT_FALSE(c.select);
  EXPECT_EQ(c.insert_mm_s, -5.0);
}

TEST(DeviceDrive, RetrieveSelectsTheStentAndStopsAtThePassEnd) {
  DeviceDrive d;
  DriveCommand c = d.update(kE, stack(kGuide, 20.0, 20.0F));
  EXPECT_TRUE(c.driving);
  ASSERT_TRUE(c.select);
  EXPECT_EQ(*c.select, kStent);
  c = d.update(kNone, stack(kStent, 50.0, 20.0F));
  EXPECT_EQ(c.insert_mm_s, -DeviceDrive::kRetrieve_mm_s);
  EXPECT_EQ(c.insert_mm_s, -10.0);
  c = d.update(kNone, stack(kStent, 47.0, 20.0F, true));
  EXPECT_EQ(c.insert_mm_s, -10.0) << "the pass is running: on";
  EXPECT_EQ(d.hints(stack(kStent, 47.0, 20.0F, true), {}).back(), "E: RETRIEVING at 10 mm/s, pass running (E, arrows or Tab: stop)");
  c = d.update(kNone, stack(kStent, 30.0, 4.0F, true));
  EXPECT_EQ(c.insert_mm_s, -10.0);
  c = d.update(kNone, stack(kStent, 28.0, 0.0F, false));
  EXPECT_FALSE(c.driving);
  EXPECT_EQ(c.note, "E: the stent is back in a catheter: the pass has ended");
  c = d.update(kE, stack(kStent, 28.0, 0.0F));
  EXPECT_FALSE(c.driving);
  EXPECT_EQ(c.note, "E: the stent is not unsheathed");
}

TEST(DeviceDrive, RetrieveStopsWhenThePassEndsEvenIfTheSnapshotLagsTheStent) {
  DeviceDrive d;
  (void)d.update(kE, stack(kStent, 50.0, 20.0F));
  (void)d.update(kNone, stack(kStent, 47.0, 20.0F, true));
  const DriveCommand c = d.update(kNone, stack(kStent, 30.0, 0.5F, false));
  EXPECT_FALSE(c.driving) << "the pass was running and has ended";
}

TEST(DeviceDrive, ArrowsTabOrTheSameKeyCancelAndTheOtherKeySwitches) {
  DeviceDrive d;
  EXPECT_TRUE(d.update(kU, stack(kMicro, 56.0, 0.0F)).driving);
  DriveCommand c = d.update(kArrow, stack(kMicro, 55.0, 2.0F));
  EXPECT_FALSE(c.driving);
  EXPECT_EQ(c.note, "U: unsheathing stopped");
  EXPECT_FALSE(d.update(kNone, stack(kMicro, 55.0, 2.0F)).driving) << "stays stopped";
  EXPECT_FALSE(d.update(kArrow, stack(kMicro, 55.0, 2.0F)).driving) << "an arrow alone starts nothing";

  EXPECT_TRUE(d.update(kU, stack(kMicro, 55.0, 2.0F)).driving);
  c = d.update(kU, stack(kMicro, 54.0, 4.0F));
  EXPECT_FALSE(c.driving) << "U again";
  EXPECT_EQ(d.mode(), DeviceDrive::Mode::kIdle);

  EXPECT_TRUE(d.update(kU, stack(kMicro, 54.0, 4.0F)).driving);
  c = d.update(kE, stack(kMicro, 53.0, 6.0F));
  EXPECT_TRUE(c.driving) << "E while unsheathing: the retrieval instead";
  EXPECT_EQ(d.mode(), DeviceDrive::Mode::kRetrieve);
  ASSERT_TRUE(c.select);
  EXPECT_EQ(*c.select, kStent);
  c = d.update(kArrow, stack(kStent, 50.0, 6.0F));
  EXPECT_FALSE(c.driving);
  EXPECT_EQ(c.note, "E: retrieval stopped");
}

TEST(DeviceDrive, StopsAtTheEndOfTheRunOrTheHub) {
  DeviceDrive d;
  EXPECT_TRUE(d.update(kU, stack(kMicro, 56.0, 0.0F)).driving);
  session::SceneSnapshot over = stack(kMicro, 50.0, 10.0F);
  over.run_over = true;
  EXPECT_FALSE(d.update(kNone, over).driving);
  EXPECT_TRUE(d.update(kU, stack(kMicro, 1.0, 10.0F)).driving);
  EXPECT_FALSE(d.update(kNone, stack(kMicro, 0.0, 10.0F)).driving) << "the microcatheter out to its hub";
}

TEST(DeviceDrive, HintsNameTheKeysWhenIdle) {
  const DeviceDrive d;
  const std::vector<std::string> names{"guide", "microcatheter", "stent"};
  std::vector<std::string> h = d.hints(stack(kStent, 50.0, 0.0F), names);
  ASSERT_EQ(h.size(), 1U) << "nothing out: nothing to retrieve";
  EXPECT_EQ(h[0], "U: unsheathe the stent (0 / 20 mm out; the microcatheter back at 5 mm/s)");
  h = d.hints(stack(kStent, 50.0, 20.0F), names);
  ASSERT_EQ(h.size(), 2U);
  EXPECT_EQ(h[0], "U: the stent is unsheathed (20 / 20 mm)");
  EXPECT_EQ(h[1], "E: retrieve the stent (back at 10 mm/s into a catheter)");
}

TEST(DeviceDrive, RefusedWhileABoxHoldsTheHandAndARunningDriveStops) {
  DeviceDrive d;
  DriveCommand c = d.update(kUBox, stack(kMicro, 56.0, 0.0F));
  EXPECT_FALSE(c.driving);
  EXPECT_FALSE(c.select) << "no tool selected under the box's hand";
  EXPECT_EQ(c.note, "U: refused while a box drives the tools (draw the catheter back on the box)");
  c = d.update(kEBox, stack(kStent, 50.0, 20.0F));
  EXPECT_FALSE(c.driving);
  EXPECT_FALSE(c.select);
  EXPECT_EQ(c.note, "E: refused while a box drives the tools (pull the stent back on the box)");
  EXPECT_EQ(d.mode(), DeviceDrive::Mode::kIdle);
  const std::vector<std::string> names{"guide", "microcatheter", "stent"};
  EXPECT_EQ(d.hints(stack(kStent, 50.0, 8.0F), names), std::vector<std::string>{"U, E: off while a box drives the tools (8 / 20 mm of the stent out)"});
  EXPECT_TRUE(d.update(kE, stack(kStent, 50.0, 20.0F)).driving) << "the box gone: E drives again";
  c = d.update(kBox, stack(kStent, 48.0, 20.0F));
  EXPECT_FALSE(c.driving) << "a box connected during a drive stops it";
  EXPECT_EQ(c.note, "a box drives the tools: the drive stops");
  EXPECT_EQ(d.mode(), DeviceDrive::Mode::kIdle);
  EXPECT_TRUE(d.update(kBox, stack(kStent, 48.0, 20.0F)).note.empty()) << "said once";
  EXPECT_EQ(d.hints(stack(kStent, 48.0, 20.0F), names).size(), 1U);
}

}  // namespace
}  // namespace cathbox::app
