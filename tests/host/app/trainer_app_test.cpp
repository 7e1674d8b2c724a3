// The trainer application without a window: the headless summary run (the scripted hand in
// virtual time, recorded) and the refusals that happen before any window opens.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/server_link.hpp"
#include "app/trainer_app.hpp"
#include "base/exit_codes.hpp"

namespace cathbox::app {
namespace {

namespace fs = std::filesystem;

class TrainerAppTest : public ::testing::Test {
 protected:
  void SetUp() override {
    home_ = fs::temp_directory_path() / ("cathbox_trainer_app_" + std::to_string(::getpid()));
    fs::remove_all(home_);
    for (const char* v : {"XDG_CONFIG_HOME", "XDG_DATA_HOME", "XDG_CACHE_HOME"}) {
      const fs::path dir = home_ / v;
      fs::create_directories(dir);
      ::setenv(v, dir.c_str(), 1);
    }
    ::unsetenv("CATHBOX_PASSWORD");
  }
  void TearDown() override { fs::remove_all(home_); }

  [[nodiscard]] TrainerOptions headless() const {
    TrainerOptions o;
    o.headless = true;
    o.box = BoxChoice::kNone;
    o.case_path = std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_right_ica.case";
    o.records_dir = (home_ / "records").string();
    o.max_seconds = 0.3;
    return o;
  }

  fs::path home_;
};

TEST_F(TrainerAppTest, HeadlessRunIsRecorded) {
  TrainerApp app(headless(), ".");
  EXPECT_EQ(app.run(), base::kExitOk);
  std::size_t records = 0;
  for (const auto& entry : fs::directory_iterator(home_ / "records")) records += entry.is_regular_file() ? 1 : 0;
  EXPECT_EQ(records, 1u);
}

// Given --emu, the headless run goes through the box (the emulator started beside this test's
// executable), in real time, not through the scripted hand (issue 29).
TEST_F(TrainerAppTest, HeadlessRunWithEmuGoesThroughTheBox) {
  TrainerOptions o = headless();
  o.box = BoxChoice::kEmulator;
  o.max_seconds = 0.2;
  const std::string bin = fs::read_symlink("/proc/self/exe").parent_path().string();
  ASSERT_TRUE(fs::exists(bin + "/cathbox-emu")) << bin;
  TrainerApp app(o, bin);
  ::testing::internal::CaptureStdout();
  const int code = app.run();
  const std::string out = ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(code, base::kExitOk);
  EXPECT_NE(out.find("with the emulated box (started)"), std::string::npos) << out;
  EXPECT_NE(out.find("(real time)"), std::string::npos) << out;
  EXPECT_NE(out.find("haptic ticks in real time"), std::string::npos) << out;
  EXPECT_EQ(out.find("scripted hand"), std::string::npos) << out;
}

TEST_F(TrainerAppTest, AssignmentWithoutServerIsRefused) {
  TrainerOptions o = headless();
  o.assignment = 3;
  TrainerApp app(o, ".");
  EXPECT_EQ(app.run(), base::kExitBadInput);
  EXPECT_FALSE(fs::exists(home_ / "records"));
}

TEST_F(TrainerAppTest, DamagedSettingsFileIsRefused) {
  TrainerOptions o = headless();
  o.settings_file = (home_ / "trainer.json").string();
  std::ofstream(o.settings_file) << R"({"usr": "trainee"})";
  TrainerApp app(o, ".");
  EXPECT_EQ(app.run(), base::kExitBadInput);
}

TEST_F(TrainerAppTest, MissingCaseIsRefused) {
  TrainerOptions o = headless();
  o.case_path = (home_ / "missing.case").string();
  TrainerApp app(o, ".");
  EXPECT_EQ(app.run(), base::kExitBadInput);
}

// --pedal-gpio: a bad value is bad input (2), a chip that is not there no device (3); both
// before any window opens.
TEST_F(TrainerAppTest, ABadOrMissingFootPedalIsRefused) {
  TrainerOptions o = headless();
  o.frames = 1;  // the windowed path, where the pedal is used
  o.pedal_gpio = "gpiochip0";
  EXPECT_EQ(TrainerApp(o, ".").run(), base::kExitBadInput);
  o.pedal_gpio = "no_such_gpiochip:22";
  EXPECT_EQ(TrainerApp(o, ".").run(), base::kExitNoDevice);
}

// The live frame carries the fluoroscopy unit's pedal and time when the case has one.
TEST(LiveFrame, CarriesFluoroscopyOnAndTime) {
  session::SceneSnapshot snap;
  auto frame = nlohmann::json::parse(ServerLink::frame_json(snap, 1, {}));
  EXPECT_FALSE(frame.contains("fluoro"));  // no vessel network: no unit
  snap.fluoro.available = true;
  snap.fluoro.image.beam_on = true;
  snap.fluoro.exposure.fluoro_time_s = 1.5;
  frame = nlohmann::json::parse(ServerLink::frame_json(snap, 2, {}));
  EXPECT_EQ(frame["fluoro"], (nlohmann::json{{"on", true}, {"time_s", 1.5}}));
}

// The live frame's wall force is the session's reading (converged steps), not the largest raw
// contact: an unconverged step's leftover penetration reads up to the contact cap.
TEST(LiveFrame, WallPeakIsTheSessionsReadingNotTheRawContacts) {
  session::SceneSnapshot snap;
  snap.contacts.push_back(session::ContactView{});
  snap.contacts.back().force_mN = 3500.0F;
  snap.wall_force_mN = 37.5;
  const auto frame = nlohmann::json::parse(ServerLink::frame_json(snap, 1, {}));
  EXPECT_DOUBLE_EQ(frame["forces"]["wall_peak_mN"].get<double>(), 37.5);
  EXPECT_DOUBLE_EQ(frame["contacts"][0]["f_mN"].get<double>(), 3500.0);
}

}  // namespace
}  // namespace cathbox::app
