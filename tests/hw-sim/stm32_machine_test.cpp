// The emulated STM32F411 on hand-assembled Thumb programs: an access to a register no model
// implements stops the machine naming the address and the peripheral; --trace-mmio names the
// peripheral and register of each access; WFI sleeps until SysTick wakes the core; code in
// flash waits while the flash erases.
#include "emu/stm32_machine.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace cathbox::emu {
namespace {

// A flash image: SP 0x20001000, reset at 0x08000008 (Thumb), then `code` (halfwords), then
// `literals` (words), the first literal 4-byte aligned after the code.
std::vector<uint8_t> program(const std::vector<uint16_t>& code, const std::vector<uint32_t>& literals) {
  std::vector<uint8_t> image;
  auto put32 = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) image.push_back(static_cast<uint8_t>(v >> (8 * i)));
  };
  put32(0x20001000u);
  put32(0x08000009u);
  for (const uint16_t h : code) {
    image.push_back(static_cast<uint8_t>(h));
    image.push_back(static_cast<uint8_t>(h >> 8));
  }
  while (image.size() % 4 != 0) image.push_back(0);
  for (const uint32_t w : literals) put32(w);
  return image;
}

TEST(Stm32Machine, AnUnmodelledRegisterStopsTheMachineNamingItsAddressAndPeripheral) {
  // ldr r0, [pc, #4] (= 0x40013000, SPI1); str r1, [r0]; b .
  Stm32Machine m;
  m.load_flash(program({0x4801, 0x6001, 0xE7FE, 0xBF00}, {0x40013000u}));
  EXPECT_FALSE(m.run(1000));
  EXPECT_NE(m.error().find("0x40013000"), std::string::npos) << m.error();
  EXPECT_NE(m.error().find("SPI1"), std::string::npos) << m.error();
  EXPECT_NE(m.error().find("write"), std::string::npos) << m.error();
}

TEST(Stm32Machine, TraceNamesThePeripheralAndRegisterOfEachAccess) {
  // ldr r0, [pc, #8] (GPIOC BSRR); ldr r1, [pc, #8] (1 << 29); str r1, [r0]; ldr r2, [r0, #-4] (ODR); b .
  Stm32Machine m;
  std::vector<std::string> lines;
  m.set_trace([&](const std::string& line) { lines.push_back(line); });
  m.load_flash(program({0x4802, 0x4903, 0x6001, 0xF850, 0x2C04, 0xE7FE}, {0x40020818u, 1u << 13}));
  EXPECT_TRUE(m.run(1000));
  EXPECT_EQ(m.error(), "");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[0].find("W GPIOC.BSRR @0x40020818 = 0x00002000"), std::string::npos) << lines[0];
  EXPECT_NE(lines[1].find("R GPIOC.ODR @0x40020814 = 0x00002000"), std::string::npos) << lines[1];
}

TEST(Stm32Machine, WfiSleepsUntilSysTickWakesTheCore) {
  // SysTick every 9600 cycles, no handler work: ldr r0, [pc, #12] (0xE000E010); ldr r1, [pc, #12]
  // (9599); str r1, [r0, #4] (RVR); movs r1, #3; str r1, [r0] (CSR: enable, interrupt); loop: wfi; b loop
  Stm32Machine m;
  auto image = program({0x4803, 0x4904, 0x6041, 0x2103, 0x6001, 0xBF30, 0xE7FD, 0xBF00}, {0xE000E010u, 9599u});
  image.resize(0x3C + 4, 0);
  // The vector table's SysTick entry (exception 15): a handler that returns at once (bx lr).
  const uint32_t handler = 0x08000040u | 1u;
  for (int i = 0; i < 4; ++i) image[0x3C + i] = static_cast<uint8_t>(handler >> (8 * i));
  image.push_back(0x70);  // 0x08000040: bx lr
  image.push_back(0x47);
  m.load_flash(image);
  EXPECT_TRUE(m.run(96'200));  // 1 ms and the set-up
  EXPECT_EQ(m.error(), "");
  EXPECT_EQ(m.ticks(), 10u);
  EXPECT_LT(m.instructions(), 200u);  // asleep between the ticks
}

TEST(Stm32Machine, CodeInFlashStallsWhileTheFlashErases) {
  // ldr r0, =FLASH (0x40023C00); the two keys into KEYR; CR = PSIZE x32 | SER | SNB 5, then
  // | STRT (a 128 KiB sector: 1 s); loop: adds r3, #1; b loop (in flash: RM0383 3.5, a fetch
  // waits for the erase to end).
  Stm32Machine m;
  m.load_flash(program({0x4805, 0x4906, 0x6041, 0x4906, 0x6041, 0x4906, 0x6101, 0x4906, 0x6101, 0x3301, 0xE7FD, 0xBF00},
                       {0x40023C00u, 0x45670123u, 0xCDEF89ABu, 0x22Au, 0x1022Au}));
  EXPECT_TRUE(m.run(960'000));  // 10 ms
  EXPECT_EQ(m.error(), "");
  EXPECT_LT(m.instructions(), 20u);  // the set-up only: the loop waits for the fetch
  EXPECT_TRUE(m.run(96'000'000));  // 1 s more: the erase ends at 1 s, the loop runs its last 10 ms
  EXPECT_GT(m.instructions(), 900'000u);
  EXPECT_LT(m.instructions(), 1'000'000u);
}

}  // namespace
}  // namespace cathbox::emu
