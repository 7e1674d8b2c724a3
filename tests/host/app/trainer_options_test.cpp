#include "app/trainer_options.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace cathbox::app {
namespace {

OptionsResult parse(std::vector<const char*> args) { return parse_trainer_options(args); }

TEST(TrainerOptions, DefaultsOpenTheDefaultCaseWithAnyBox) {
  const OptionsResult r = parse({});
  ASSERT_TRUE(r.options) << r.error;
  EXPECT_EQ(r.options->box, BoxChoice::kAuto);
  EXPECT_FALSE(r.options->headless);
  EXPECT_EQ(r.options->width, 1280);
  EXPECT_EQ(r.options->height, 720);
}

TEST(TrainerOptions, ParsesTheHeadlessScreenshotMode) {
  const OptionsResult r = parse({"--headless", "--frames", "30", "--screenshot", "out.png",
                                 "--size", "800x600", "--case", "cases/neuro.case", "--emu"});
  ASSERT_TRUE(r.options) << r.error;
  EXPECT_TRUE(r.options->headless);
  EXPECT_EQ(r.options->frames, 30);
  EXPECT_EQ(r.options->screenshot, "out.png");
  EXPECT_EQ(r.options->width, 800);
  EXPECT_EQ(r.options->height, 600);
  EXPECT_EQ(r.options->case_path, "cases/neuro.case");
  EXPECT_EQ(r.options->box, BoxChoice::kEmulator);
  EXPECT_TRUE(r.options->emu_socket.empty());
}

TEST(TrainerOptions, ViewPicksTheFluoroscopicImageOrThe3dTree) {
  EXPECT_FALSE(parse({}).options->view) << "the case decides";
  EXPECT_EQ(parse({"--view", "fluoro"}).options->view, MainView::kFluoro);
  EXPECT_EQ(parse({"--view=3d"}).options->view, MainView::k3d);
  for (const char* bad : {"xray", ""}) {
    const OptionsResult r = parse({"--view", bad});
    EXPECT_FALSE(r.options);
    EXPECT_EQ(r.error, "--view needs fluoro or 3d");
  }
}

TEST(TrainerOptions, EmuTakesAnOptionalSocketPath) {
  const OptionsResult r = parse({"--emu", "/tmp/box.sock", "--bench", "2.5"});
  ASSERT_TRUE(r.options) << r.error;
  EXPECT_EQ(r.options->emu_socket, "/tmp/box.sock");
  EXPECT_DOUBLE_EQ(r.options->bench_seconds, 2.5);
}

TEST(TrainerOptions, SpeedPacesTheHeadlessRun) {
  const OptionsResult r = parse({"--headless", "--speed", "1", "--seconds", "8"});
  ASSERT_TRUE(r.options) << r.error;
  EXPECT_DOUBLE_EQ(r.options->speed, 1.0);
  EXPECT_DOUBLE_EQ(r.options->max_seconds, 8.0);
  EXPECT_DOUBLE_EQ(parse({"--headless"}).options->speed, 0.0);
}

TEST(TrainerOptions, BoxesAreKeptInTheOrderGiven) {
  const OptionsResult r = parse({"--box", "catheter=emu", "--box", "guidewire=CBX-0042", "--box", "coil=emu:/tmp/c.sock"});
  ASSERT_TRUE(r.options) << r.error;
  EXPECT_EQ(r.options->boxes, (std::vector<std::string>{"catheter=emu", "guidewire=CBX-0042", "coil=emu:/tmp/c.sock"}));
}

TEST(TrainerOptions, ParsesTheServerOptions) {
  const OptionsResult r = parse({"--server", "http://127.0.0.1:8080", "--user", "ann", "--password-file", "/etc/pw",
                                 "--rig", "rig-07", "--assignment", "12", "--settings", "/etc/t.json"});
  ASSERT_TRUE(r.options) << r.error;
  EXPECT_EQ(r.options->server_url, "http://127.0.0.1:8080");
  EXPECT_EQ(r.options->server_user, "ann");
  EXPECT_EQ(r.options->password_file, "/etc/pw");
  EXPECT_EQ(r.options->rig, "rig-07");
  EXPECT_EQ(r.options->assignment, 12);
  EXPECT_EQ(r.options->settings_file, "/etc/t.json");
}

TEST(TrainerOptions, TakesAFootPedalLine) {
  const OptionsResult r = parse({"--pedal-gpio", "gpiochip0:22"});
  ASSERT_TRUE(r.options) << r.error;
  EXPECT_EQ(r.options->pedal_gpio, "gpiochip0:22");
  EXPECT_TRUE(parse({}).options->pedal_gpio.empty());
}

TEST(TrainerOptions, BadInputGivesOneLineNamingTheOption) {
  const std::vector<std::pair<std::vector<const char*>, const char*>> bad = {
      {{"--frames"}, "--frames"},
      {{"--headless", "--frames", "0"}, "--frames"},
      {{"--headless", "--frames", "12x"}, "--frames"},
      {{"--size", "100"}, "--size"},
      {{"--size", "10x10"}, "--size"},
      {{"--bench", "-1"}, "--bench"},
      {{"--screenshot", "a.png"}, "--screenshot"},
      {{"--frames", "3"}, "--headless"},
      {{"--colour"}, "--colour"},
      {{"-\n"}, "-\\x0a"},
      {{"--server", "ftp://x"}, "--server"},
      {{"--server"}, "--server"},
      {{"--user", ""}, "--user"},
      {{"--assignment", "0"}, "--assignment"},
      {{"--assignment", "7a"}, "--assignment"},
      {{"--password-file"}, "--password-file"},
      {{"--headless", "--speed", "-1"}, "--speed"},
      {{"--box", "catheter"}, "--box"},
      {{"--box", "=emu", "--box", "guidewire=emu"}, "--box"},
      {{"--box", "catheter=emu"}, "--box"},
      {{"--box", "catheter=emu", "--box", "guidewire=emu", "--no-box"}, "--box"},
      {{"--box", "catheter=emu", "--box", "guidewire=emu", "--emu"}, "--box"},
      {{"--headless", "--speed", "fast"}, "--speed"},
      {{"--speed", "1"}, "--speed"},
      {{"--headless", "--frames", "2", "--speed", "1"}, "--speed"},
  };
  for (const auto& [args, name] : bad) {
    const OptionsResult r = parse(args);
    EXPECT_FALSE(r.options) << name;
    EXPECT_NE(r.error.find(name), std::string::npos) << r.error;
    EXPECT_EQ(r.error.find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace cathbox::app
