// Which real box a rig's `--box TOOL=SERIAL` opens: the hidraw path of the box with that serial
// among those hidapi enumerates (the enumeration itself needs USB, absent here).
#include <gtest/gtest.h>

#include <vector>

#include "device/box_opener.hpp"

namespace cathbox::device {
namespace {

TEST(BoxOpener, PathOfSerialPicksTheBoxOrNamesTheSerialsFound) {
  const std::vector<HidDeviceInfo> boxes = {{"/dev/hidraw3", "CBX-0041", "Cathbox", 0x1209, 0xcb01},
                                            {"/dev/hidraw5", "CBX-0042", "Cathbox", 0x1209, 0xcb01},
                                            {"/dev/hidraw7", "", "Cathbox", 0x1209, 0xcb01}};
  auto right = path_of_serial(boxes, "CBX-0042");
  ASSERT_TRUE(right) << right.error().message;
  EXPECT_EQ(right.value(), "/dev/hidraw5");
  auto missing = path_of_serial(boxes, "CBX-0099");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().message,
            "no box with serial 'CBX-0099' (found: CBX-0041, CBX-0042, (no serial) /dev/hidraw7)");
  auto none = path_of_serial({}, "CBX-0041");
  ASSERT_FALSE(none);
  EXPECT_EQ(none.error().message, "no box with serial 'CBX-0041' (no box found)");
}

}  // namespace
}  // namespace cathbox::device
