// The STM32F411 port's USB OTG FS driver (usb_otgfs.c), its USB glue (usb_device.c) and its HAL
// (board.c), built for the host with their register blocks in RAM (regs_in_ram.h), driving the
// firmware core: what happens to the outputs on a bus reset or suspend, and to the state
// reports when the endpoint's TX FIFO has no room.
#include <gtest/gtest.h>

#include <cstring>

#include "regs_in_ram.h"
extern "C" {
#include "board.h"
#include "cbx_build_id.h"
#include "firmware/cbx_core.h"
#include "stm32f411_regs.h"
#include "usb_device.h"
#include "usb_otgfs.h"
void OTG_FS_IRQHandler(void);
}

extern "C" {
uint32_t cbx_test_periph[0x24000u / 4u];
uint32_t cbx_test_otg[0x3000u / 4u];
uint32_t cbx_test_scs[0x1000u / 4u];
uint32_t cbx_test_sysmem[0x8000u / 4u];
// The settings store (flash_store.c is Cortex-M code): empty, saves accepted.
bool cbx_hal_store_load(void*, size_t) { return false; }
bool cbx_hal_store_save(const void*, size_t) { return true; }
}

namespace {

constexpr uint32_t kEnablePin = 14u;

class UsbOtgfs : public testing::Test {
 protected:
  void SetUp() override {
    std::memset(cbx_test_periph, 0, sizeof cbx_test_periph);
    std::memset(cbx_test_otg, 0, sizeof cbx_test_otg);
    std::memset(cbx_test_scs, 0, sizeof cbx_test_scs);
    ADC1_JDR(1) = 2048u;  // 1650 mV: no current
    ADC1_JDR(2) = 2048u;
    OTG_GINTMSK = GINT_USBRST | GINT_ENUMDNE | GINT_RXFLVL | GINT_IEPINT | GINT_OEPINT | GINT_USBSUSP |
                  GINT_WKUPINT | GINT_SOF;  // as usb_otgfs_init() leaves it
    cbx_core_config config;
    board_core_config(&config, hse_started_);
    config.axis[0].actuator = config.axis[1].actuator = CBX_ACTUATOR_MOTOR;
    cbx_core_init(&core_, &config);
    usb_device_bind(&core_);
    Interrupt(GINT_USBRST);  // the host resets the bus, then configures the device
    const usb_setup set_configuration{0x00, 9, 1, 0, 0};
    ASSERT_TRUE(usb_device_setup(&set_configuration));
    Calibrate();
  }

  // One interrupt of the OTG core with `status` pending (and, for IN endpoint 1, XFRC).
  void Interrupt(uint32_t status) {
    OTG_GINTSTS = status;
    OTG_IRQHandler_();
  }
  static void OTG_IRQHandler_() { OTG_FS_IRQHandler(); }

  void Calibrate() {
    cbx_calibration c{};
    c.header.version = CBX_PROTOCOL_VERSION;
    c.insertion_counts_per_m = 108650u;
    c.rotation_counts_per_rev = 4096u;
    c.insertion_full_scale_mN = 5000u;
    c.rotation_full_scale_uNm = 50000u;
    for (unsigned i = 0; i < CBX_CURVE_POINTS; ++i) {
      const auto v = static_cast<uint16_t>(250u * (i + 1u));
      c.insertion_curve[i] = c.rotation_curve[i] = {v, v};
    }
    uint8_t report[CBX_REPORT_SIZE];
    ASSERT_EQ(cbx_calibration_encode(&c, report), CBX_OK);
    ASSERT_EQ(cbx_core_usb_feature_set(&core_, report, sizeof report), CBX_OK);
  }

  // A command over interrupt OUT, as the driver hands it to the glue.
  void Command(uint8_t mode, int32_t force_mN) {
    cbx_command_report c{};
    c.header = {CBX_PROTOCOL_VERSION, ++seq_, TIM5->CNT};
    c.mode = mode;
    c.insertion = {force_mN, 0, 0, 0, -5000, 5000};
    c.rotation = {0, 0, 0, 0, -1000, 1000};
    uint8_t report[CBX_REPORT_SIZE];
    ASSERT_EQ(cbx_command_encode(&c, report), CBX_OK);
    usb_device_ep1_out(report, sizeof report);
  }

  // The SysTick handler: ADC latch, then the core's control tick, 100 us later.
  void Tick() {
    TIM5->CNT = TIM5->CNT + CBX_CORE_TICK_US;
    ADC1_SR = ADC1_SR | ADC_SR_JEOC;
    board_adc_cycle();
    cbx_core_control_tick(&core_);
  }
  void RunMs(int ms) {
    for (int i = 0; i < 10 * ms; ++i) Tick();
  }

  // What a host reading the state (GET_REPORT) gets now.
  cbx_state_report State() {
    uint8_t bytes[CBX_REPORT_SIZE];
    cbx_state_report s{};
    EXPECT_EQ(cbx_core_usb_feature_get(&core_, CBX_ID_STATE, bytes), CBX_OK);
    EXPECT_EQ(cbx_state_decode(bytes, sizeof bytes, &s), CBX_OK);
    return s;
  }

  // Pushing at 1.5 N in motor mode: the insertion PWM is on.
  void Render() {
    for (int ms = 0; ms < 5; ++ms) {
      Command(CBX_MODE_MOTOR, 1500);
      RunMs(1);
    }
    ASSERT_GT(TIM4->CCR1, 0u);
    ASSERT_TRUE(State().status & CBX_STATUS_OUTPUT_ENABLED);
  }

  static bool OutputsCut() {
    return TIM4->CCR1 == 0u && TIM4->CCR2 == 0u && GPIOB->BSRR == (1u << (kEnablePin + 16u));
  }

  // A frame start with `words` of room in endpoint 1's TX FIFO; true if a report was queued.
  bool StartOfFrame(uint32_t words) {
    OTG_DTXFSTS(1) = words;
    OTG_DIEPCTL(1) = OTG_DIEPCTL(1) & ~EPCTL_EPENA;
    Interrupt(GINT_SOF);
    return (OTG_DIEPCTL(1) & EPCTL_EPENA) != 0u && OTG_DIEPTSIZ(1) == (EPTSIZ_PKTCNT1 | CBX_REPORT_SIZE);
  }
  // The host took the queued report.
  void InTransferComplete() {
    OTG_DAINT = 1u << 1;
    OTG_DIEPINT(1) = EPINT_XFRC;
    Interrupt(GINT_IEPINT);
  }

  cbx_core core_{};
  uint16_t seq_ = 0;
  bool hse_started_ = true;
};

class UsbOtgfsWithoutCrystal : public UsbOtgfs {
 protected:
  void SetUp() override {
    hse_started_ = false;
    UsbOtgfs::SetUp();
  }
};

TEST_F(UsbOtgfs, BusResetZeroesTheOutputsAtOnceAndTheNextTickKeepsThemOff) {
  Render();
  Interrupt(GINT_USBRST);
  EXPECT_TRUE(OutputsCut()) << "CCR1 " << TIM4->CCR1;
  Tick();
  EXPECT_EQ(TIM4->CCR1, 0u);
  RunMs(60);  // past the watchdog: no fault, the box just stopped (the host went away)
  const cbx_state_report s = State();
  EXPECT_EQ(TIM4->CCR1, 0u);
  EXPECT_EQ(s.mode, CBX_MODE_OFF);
  EXPECT_FALSE(s.status & CBX_STATUS_OUTPUT_ENABLED);
  EXPECT_EQ(s.faults & CBX_FAULT_WATCHDOG, 0u);
}

TEST_F(UsbOtgfs, SuspendZeroesTheOutputsAtOnce) {
  Render();
  Interrupt(GINT_USBSUSP);
  EXPECT_TRUE(OutputsCut()) << "CCR1 " << TIM4->CCR1;
  Tick();
  EXPECT_EQ(TIM4->CCR1, 0u);
  EXPECT_EQ(State().mode, CBX_MODE_OFF);
  // Resumed, the host sends commands again and the box renders them.
  Interrupt(GINT_WKUPINT);
  Render();
}

TEST_F(UsbOtgfs, ReportsDroppedForAFullTxFifoAreCountedAndTheCommandAckStillArrives) {
  Render();
  ASSERT_TRUE(StartOfFrame(16u));  // 64 bytes of room: sent
  InTransferComplete();
  RunMs(1);
  EXPECT_FALSE(StartOfFrame(15u));  // one word short: not sent
  RunMs(1);
  EXPECT_FALSE(StartOfFrame(0u));
  EXPECT_EQ(State().in_dropped, 2u);
  // A command arrives while the FIFO is full; its ACK (the echo of its seq) goes out in the
  // next report that fits, together with the count.
  Command(CBX_MODE_MOTOR, 1200);
  const uint16_t acked = seq_;
  RunMs(1);
  ASSERT_TRUE(StartOfFrame(16u));
  const cbx_state_report s = State();
  EXPECT_EQ(s.command_seq_echo, acked);
  EXPECT_EQ(s.in_dropped, 2u);
  // A control transfer's status stage (the ACK of a SET_REPORT) does not need endpoint 1's
  // FIFO: it goes out while that FIFO is full.
  OTG_DTXFSTS(1) = 0u;
  OTG_DIEPCTL(0) = 0u;
  usb_ep0_status();
  EXPECT_TRUE(OTG_DIEPCTL(0) & EPCTL_EPENA);
  EXPECT_EQ(OTG_DIEPTSIZ(0), EPTSIZ_PKTCNT1);
}

// What the port tells the core: the chip's serial, the image's version and build, and no HSE
// fault when the crystal started.
TEST_F(UsbOtgfs, TheCoreReportsTheBoardAndTheImage) {
  uint8_t bytes[CBX_REPORT_SIZE];
  ASSERT_EQ(cbx_core_usb_feature_get(&core_, CBX_ID_DEVICE_INFO, bytes), CBX_OK);
  cbx_device_info info{};
  ASSERT_EQ(cbx_device_info_decode(bytes, sizeof bytes, &info), CBX_OK);
  EXPECT_STREQ(info.board, CBX_BOARD_NAME);
  EXPECT_STREQ(info.serial, "CBX-000000000000");  // the unique ID reads 0 here
  EXPECT_EQ(info.fw_major, CBX_FW_MAJOR);
  EXPECT_STREQ(info.build, CBX_BUILD_ID);
  EXPECT_EQ(State().board_faults, 0u);
}

// board_clock_init() found no crystal: every state report carries the HSE board fault, and the
// box still renders (USB timing is out of spec, the haptics are not).
TEST_F(UsbOtgfsWithoutCrystal, EveryStateReportCarriesTheHseFaultAndTheBoxStillRenders) {
  EXPECT_EQ(State().board_faults, CBX_BOARD_FAULT_HSE);
  Render();
  EXPECT_EQ(State().board_faults, CBX_BOARD_FAULT_HSE);
  EXPECT_EQ(State().faults, 0u);
}

}  // namespace
