#include "app/box_hand.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <optional>
#include <thread>

#include "device/box_client.hpp"
#include "device/box_opener.hpp"
#include "device/clock.hpp"
#include "protocol/cbx_command_report.h"
#include "tool/force_law.hpp"

extern char** environ;

namespace cathbox::app {
namespace {

constexpr double kTwoPi = 6.283185307179586;

std::int32_t clamp_i32(double v) {
  return static_cast<std::int32_t>(std::clamp(std::llround(v), static_cast<long long>(INT32_MIN),
                                              static_cast<long long>(INT32_MAX)));
}

// cathbox-emu as a child process on a socket of its own; stopped (SIGTERM) when destroyed.
class EmulatorProcess {
 public:
  static std::unique_ptr<EmulatorProcess> start(const std::string& program, const std::string& socket,
                                                std::string& error) {
    std::vector<std::string> args = {program, "--socket", socket};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (posix_spawn(&pid, program.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
      error = program + ": cannot start the emulated box";
      return nullptr;
    }
    return std::unique_ptr<EmulatorProcess>(new EmulatorProcess(pid));
  }
  ~EmulatorProcess() {
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  EmulatorProcess(const EmulatorProcess&) = delete;
  EmulatorProcess& operator=(const EmulatorProcess&) = delete;
  [[nodiscard]] bool running() const {
    int status = 0;
    return waitpid(pid_, &status, WNOHANG) == 0;
  }

 private:
  explicit EmulatorProcess(pid_t pid) : pid_(pid) {}
  pid_t pid_;
};

}  // namespace

cbx_command_report box_command(const tool::ForceLaw& law, const BoxOrigin& origin, std::uint8_t mode) {
  // out = offset - k (pos - pos0) - b vel (protocol/README.md); 1 mN mm = 1 uN m.
  cbx_command_report c{};
  c.mode = mode;
  const double ins_origin_um = static_cast<double>(origin.insertion_count0) / origin.counts_per_mm * 1000.0;
  c.insertion.offset = clamp_i32(-law.force0_mN);
  c.insertion.pos0 = clamp_i32(law.insertion0_mm * 1000.0 + ins_origin_um);
  c.insertion.stiffness = clamp_i32(std::max(0.0, law.stiffness_mN_per_mm) * 1000.0);
  c.insertion.damping = clamp_i32(std::max(0.0, law.damping_mN_s_per_mm) * 1000.0);
  c.insertion.out_min = INT32_MIN;
  c.insertion.out_max = INT32_MAX;
  const double rot_origin_urad = static_cast<double>(origin.rotation_count0) / origin.counts_per_rad * 1e6;
  c.rotation.offset = clamp_i32(-law.torque0_mNmm);
  c.rotation.pos0 = clamp_i32(law.rotation0_rad * 1e6 + rot_origin_urad);
  c.rotation.stiffness = clamp_i32(std::max(0.0, law.torsion_stiffness_mNmm_per_rad));
  c.rotation.damping = clamp_i32(std::max(0.0, law.torsion_damping_mNmm_s_per_rad));
  c.rotation.out_min = INT32_MIN;
  c.rotation.out_max = INT32_MAX;
  return c;
}

struct BoxHand::Impl {
  device::SystemClock clock;
  std::unique_ptr<EmulatorProcess> emulator;
  std::string socket;
  std::unique_ptr<device::BoxClient> client;
  device::BoxState state;
  double counts_per_mm = 0.0;
  double counts_per_rad = 0.0;
  bool have_origin = false;
  std::int32_t insertion0 = 0;
  std::int32_t rotation0 = 0;
  std::uint8_t mode = CBX_MODE_BRAKE;
  std::string kind;
};

BoxHand::BoxHand(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

BoxHand::~BoxHand() {
  if (impl_ && impl_->client) release();
  if (impl_) impl_->client.reset();  // before the emulator goes
}

std::unique_ptr<BoxHand> BoxHand::connect(BoxChoice choice, const std::string& emu_socket,
                                          const std::string& emu_program, std::string& error) {
  auto impl = std::make_unique<Impl>();
  if (choice == BoxChoice::kNone) {
    error = "no box requested";
    return nullptr;
  }
  if (choice == BoxChoice::kAuto) {
    auto real = device::BoxClient::connect(device::box_opener(std::nullopt, impl->clock), impl->clock);
    if (real) {
      impl->client = std::move(real.value());
      impl->kind = "box";
    }
  }
  if (!impl->client) {
    impl->socket = emu_socket;
    if (impl->socket.empty()) {
      impl->socket = "/tmp/cathbox-trainer-" + std::to_string(getpid()) + ".sock";
      impl->emulator = EmulatorProcess::start(emu_program, impl->socket, error);
      if (!impl->emulator) return nullptr;
    }
    // The emulator needs a moment to bind its socket: retry for up to 3 s.
    std::string last;
    for (int attempt = 0; attempt < 60 && !impl->client; ++attempt) {
      auto c = device::BoxClient::connect(device::box_opener(impl->socket, impl->clock), impl->clock);
      if (c) {
        impl->client = std::move(c.value());
      } else {
        last = c.error().message;
        if (impl->emulator && !impl->emulator->running()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    if (!impl->client) {
      error = "emulated box at " + impl->socket + ": " + last;
      return nullptr;
    }
    impl->kind = impl->emulator ? "emulated box (started)" : "emulated box";
  }
  auto cal = impl->client->calibration();
  if (!cal) {
    error = cal.error().message;
    return nullptr;
  }
  if (cal.value().insertion_counts_per_m == 0 || cal.value().rotation_counts_per_rev == 0) {
    error = impl->client->describe() + " is not calibrated (run 'cathbox calibrate')";
    return nullptr;
  }
  impl->counts_per_mm = cal.value().insertion_counts_per_m / 1000.0;
  impl->counts_per_rad = cal.value().rotation_counts_per_rev / kTwoPi;
  const cbx_device_info& info = impl->client->device_info();
  impl->mode = info.insertion_actuator == CBX_ACTUATOR_MOTOR ? CBX_MODE_MOTOR : CBX_MODE_BRAKE;
  return std::unique_ptr<BoxHand>(new BoxHand(std::move(impl)));
}

BoxReading BoxHand::poll() {
  BoxReading r;
  Impl& m = *impl_;
  r.fresh = m.client->poll(m.state);
  r.link_up = m.client->link() == device::Link::kUp;
  const cbx_state_report& s = m.state.report;
  if (r.fresh && !m.have_origin) {
    m.have_origin = true;
    m.insertion0 = s.insertion_count;
    m.rotation0 = s.rotation_count;
  }
  if (m.have_origin) {
    r.insertion_mm = static_cast<double>(s.insertion_count - m.insertion0) / m.counts_per_mm;
    r.rotation_rad = static_cast<double>(s.rotation_count - m.rotation0) / m.counts_per_rad;
  }
  r.faults = s.faults;
  return r;
}

void BoxHand::send(const tool::ForceLaw& law) {
  Impl& m = *impl_;
  const BoxOrigin origin{m.counts_per_mm, m.counts_per_rad, m.insertion0, m.rotation0};
  (void)m.client->send(box_command(law, origin, m.mode));
}

void BoxHand::release() {
  cbx_command_report c{};
  c.mode = CBX_MODE_OFF;
  (void)impl_->client->send(c);
}

std::string BoxHand::describe() const { return impl_->kind + ": " + impl_->client->describe(); }

}  // namespace cathbox::app
