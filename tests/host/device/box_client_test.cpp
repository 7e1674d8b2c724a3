// BoxClient on a fake transport: the version check, draining to the newest state, counting
// rejected reports, command sequence numbers, and reconnection through its opener.
#include <gtest/gtest.h>

#include <deque>

#include "device/box_client.hpp"

namespace cathbox::device {
namespace {

class FakeClock final : public Clock {
 public:
  std::int64_t t = 0;
  std::int64_t now_us() override { return t; }
  void wait(int, std::int64_t us) override { t += us; }
};

Report state_report(uint16_t seq, int32_t count) {
  cbx_state_report s{};
  s.header.seq = seq;
  s.insertion_count = count;
  s.status = CBX_STATUS_CALIBRATED;
  Report r{};
  EXPECT_EQ(cbx_state_encode(&s, r.data()), CBX_OK);
  return r;
}

struct FakeBox {
  std::deque<Report> in;
  std::vector<Report> out;
  unsigned info_version = 1;
  bool gone = false;
  bool refuse_set = false;  // SET_REPORT stalls (a box that no longer takes the session's settings)
  int opens = 0;
};

class FakeTransport final : public Transport {
 public:
  explicit FakeTransport(FakeBox& box) : box_(box) {}
  IoStatus read_in(Report& r) override {
    if (box_.gone) return IoStatus::kDisconnected;
    if (box_.in.empty()) return IoStatus::kEmpty;
    r = box_.in.front();
    box_.in.pop_front();
    return IoStatus::kOk;
  }
  IoStatus write_out(const Report& r) override {
    if (box_.gone) return IoStatus::kDisconnected;
    box_.out.push_back(r);
    return IoStatus::kOk;
  }
  Status get_feature(uint8_t id, Report& r) override {
    if (id != CBX_ID_DEVICE_INFO) return make_error(Errc::kStall, "stall");
    cbx_device_info d{};
    std::snprintf(d.serial, sizeof d.serial, "FAKE");
    std::snprintf(d.board, sizeof d.board, "fake");
    EXPECT_EQ(cbx_device_info_encode(&d, r.data()), CBX_OK);
    if (box_.info_version != 1) {  // a future box: other major version, valid CRC
      r[1] = static_cast<uint8_t>(box_.info_version);
      cbx_report_finish(r.data());
    }
    return Ok{};
  }
  Status set_feature(const Report&) override {
    if (box_.refuse_set) return make_error(Errc::kStall, "stall");
    return Ok{};
  }
  std::string describe() const override { return "fake"; }

 private:
  FakeBox& box_;
};

BoxClient::Opener opener(FakeBox& box) {
  return [&box]() -> Result<std::unique_ptr<Transport>> {
    ++box.opens;
    if (box.gone) return make_error(Errc::kNoDevice, "unplugged");
    return std::unique_ptr<Transport>(new FakeTransport(box));
  };
}

TEST(BoxClient, IncompatibleBoxGivesTheOneLineMessage) {
  FakeBox box;
  box.info_version = 2;
  FakeClock clock;
  auto client = BoxClient::connect(opener(box), clock);
  ASSERT_FALSE(client.ok());
  EXPECT_EQ(client.error().code, Errc::kIncompatible);
  EXPECT_EQ(client.error().message,
            "the box speaks protocol v2, this host speaks v1: update the host tools (or flash firmware 1.x)");
}

TEST(BoxClient, DrainsToTheNewestValidStateAndCountsEverythingElse) {
  FakeBox box;
  FakeClock clock;
  auto client = std::move(BoxClient::connect(opener(box), clock).value());
  box.in.push_back(state_report(10, 100));
  box.in.push_back(state_report(11, 110));
  Report corrupt = state_report(12, 120);
  corrupt[20] ^= 0x04;
  box.in.push_back(corrupt);
  box.in.push_back(state_report(14, 140));  // 12 (corrupt) and 13 (lost) missing
  box.in.push_back(state_report(14, 140));  // duplicate
  box.in.push_back(state_report(13, 130));  // late
  BoxState state;
  ASSERT_TRUE(client->poll(state));
  EXPECT_EQ(state.report.header.seq, 14);
  EXPECT_EQ(state.report.insertion_count, 140);
  const auto& s = client->stats();
  EXPECT_EQ(s.states_accepted, 3u);
  EXPECT_EQ(s.states_superseded, 2u);
  EXPECT_EQ(s.rejected_crc, 1u);
  EXPECT_EQ(s.states_missed, 2u);
  EXPECT_EQ(s.states_stale, 2u);
  EXPECT_FALSE(client->poll(state));
}

TEST(BoxClient, CommandsCarryConsecutiveSequenceNumbers) {
  FakeBox box;
  FakeClock clock;
  auto client = std::move(BoxClient::connect(opener(box), clock).value());
  cbx_command_report c{};
  c.mode = CBX_MODE_BRAKE;
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(client->send(c));
  ASSERT_EQ(box.out.size(), 3u);
  for (uint16_t i = 0; i < 3; ++i) {
    cbx_command_report back;
    ASSERT_EQ(cbx_command_decode(box.out[i].data(), kReportSize, &back), CBX_OK);
    EXPECT_EQ(back.header.seq, i);
  }
  cbx_command_report invalid = c;
  invalid.mode = 7;
  EXPECT_FALSE(client->send(invalid));
  EXPECT_EQ(client->stats().commands_dropped, 1u);
}

TEST(BoxClient, ReconnectsThroughItsOpenerAndResendsTheLastCommand) {
  FakeBox box;
  FakeClock clock;
  auto client = std::move(BoxClient::connect(opener(box), clock).value());
  cbx_command_report c{};
  c.mode = CBX_MODE_BRAKE;
  ASSERT_TRUE(client->send(c));
  box.gone = true;
  BoxState state;
  EXPECT_FALSE(client->poll(state));
  EXPECT_EQ(client->link(), Link::kDown);
  EXPECT_FALSE(client->send(c));  // remembered, not delivered
  for (int i = 0; i < 5; ++i) {
    clock.t += 10'000;
    EXPECT_FALSE(client->poll(state));
  }
  const int attempts = box.opens;
  EXPECT_LE(attempts, 3);  // one attempt per reconnect interval (50 ms), not one per poll
  box.gone = false;
  box.out.clear();
  clock.t += 50'000;
  box.in.push_back(state_report(1, 5));
  EXPECT_TRUE(client->poll(state));
  EXPECT_EQ(client->link(), Link::kUp);
  EXPECT_EQ(client->stats().reconnects, 1u);
  ASSERT_EQ(box.out.size(), 1u);  // the last command went out again at once
  cbx_command_report back;
  ASSERT_EQ(cbx_command_decode(box.out[0].data(), kReportSize, &back), CBX_OK);
  EXPECT_EQ(back.header.seq, 1);  // the sequence continues (the undelivered send used none)
}

TEST(BoxClient, AFailedSessionRestoreWaitsTheReconnectIntervalAndKeepsTheOutageStart) {
  FakeBox box;
  FakeClock clock;
  auto client = std::move(BoxClient::connect(opener(box), clock).value());
  cbx_limits limits{};
  limits.max_force_mN = 1000;
  limits.max_torque_uNm = 1000;
  limits.watchdog_timeout_ms = 50;
  limits.insertion_max_current_mA = 1000;
  limits.rotation_max_current_mA = 1000;
  limits.force_slew_mN_per_ms = 10;
  limits.torque_slew_uNm_per_ms = 10;
  ASSERT_TRUE(client->set_limits(limits).ok());
  box.gone = true;
  BoxState state;
  EXPECT_FALSE(client->poll(state));
  ASSERT_EQ(client->link(), Link::kDown);
  const int opens_before = box.opens;
  // The box is back but refuses the session's limits: 1 s of polls at 1 kHz.
  box.gone = false;
  box.refuse_set = true;
  for (int i = 0; i < 1000; ++i) {
    clock.t += 1000;
    EXPECT_FALSE(client->poll(state));
  }
  EXPECT_LE(box.opens - opens_before, 21) << "one attempt per reconnect interval (50 ms), not one per poll";
  EXPECT_EQ(client->stats().disconnects, 1u);
  // It takes the limits again: the outage is measured from the first loss of the link.
  box.refuse_set = false;
  for (int i = 0; i < 60 && client->link() == Link::kDown; ++i) {
    clock.t += 1000;
    (void)client->poll(state);
  }
  ASSERT_EQ(client->link(), Link::kUp);
  EXPECT_EQ(client->stats().reconnects, 1u);
  EXPECT_GE(client->stats().last_reconnect_us, 1'000'000u);
}

}  // namespace
}  // namespace cathbox::device
