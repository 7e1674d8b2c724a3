// How the trainer starts a run, without a window: the case it opens and the hand and record it
// gives the session.
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "app/trainer_launch.hpp"

namespace cathbox::app {
namespace {

namespace fs = std::filesystem;

const std::string kCases = std::string(CATHBOX_SOURCE_DIR) + "/cases";

struct TempDir {
  fs::path path;
  TempDir() : path(fs::temp_directory_path() / ("cathbox_launch_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

TEST(TrainerLaunch, DefaultCaseOfTheCasesFolderIsTheSingleWireNeuroCase) {
  TrainerOptions options;
  options.cases_dir = kCases;
  CaseCatalog catalog;
  const CaseChoice c = choose_case(options, ".", catalog);
  ASSERT_TRUE(c.error.empty()) << c.error;
  EXPECT_EQ(fs::path(c.path).filename(), "neuro_right_ica.case");
  ASSERT_GE(c.catalog_index, 0);
  EXPECT_EQ(catalog.entries()[static_cast<std::size_t>(c.catalog_index)].name, "neuro_right_ica.case");
}

// Installed (the cathbox Debian package: /usr/bin/cathbox-trainer, /usr/share/cathbox/cases), the
// program's own cases come before the source tree's.
TEST(TrainerLaunch, TheInstalledCasesBesideTheProgramComeFirst) {
  TempDir prefix;
  const fs::path installed = prefix.path / "share/cathbox/cases";
  fs::create_directories(installed);
  fs::create_directories(prefix.path / "bin");
  fs::copy_file(kCases + "/y_bifurcation.case", installed / "y_bifurcation.case");
  TrainerOptions options;
  CaseCatalog catalog;
  const CaseChoice c = choose_case(options, (prefix.path / "bin").string(), catalog);
  ASSERT_EQ(catalog.entries().size(), 1U);
  EXPECT_EQ(catalog.entries()[0].name, "y_bifurcation.case");
  EXPECT_EQ(fs::path(c.path).parent_path().filename(), "cases");
  EXPECT_EQ(fs::canonical(fs::path(c.path).parent_path()), fs::canonical(installed));
}

TEST(TrainerLaunch, AskedCaseIsOpenedAndMarkedInThePicker) {
  TrainerOptions options;
  options.cases_dir = kCases;
  options.case_path = kCases + "/y_bifurcation.case";
  CaseCatalog catalog;
  const CaseChoice c = choose_case(options, ".", catalog);
  EXPECT_EQ(c.path, options.case_path);
  ASSERT_GE(c.catalog_index, 0);
  EXPECT_EQ(catalog.entries()[static_cast<std::size_t>(c.catalog_index)].name, "y_bifurcation.case");
}

TEST(TrainerLaunch, AFolderWithoutCasesIsOneLine) {
  TempDir empty;
  TrainerOptions options;
  options.cases_dir = empty.path.string();
  CaseCatalog catalog;
  const CaseChoice c = choose_case(options, ".", catalog);
  EXPECT_TRUE(c.path.empty());
  EXPECT_NE(c.error.find("no case files"), std::string::npos) << c.error;
  EXPECT_EQ(c.error.find('\n'), std::string::npos);
}

TEST(TrainerLaunch, ScriptedRunIsRecordedIntoTheRecordsFolder) {
  TempDir records;
  TrainerOptions options;
  options.box = BoxChoice::kNone;
  options.records_dir = records.path.string();
  session::KeyboardInput keyboard;
  LiveSession live = open_live_session(options, ".", kCases + "/neuro_right_ica.case", true, keyboard);
  ASSERT_NE(live.session, nullptr) << live.error;
  EXPECT_TRUE(live.error.empty());
  ASSERT_FALSE(live.record_path.empty()) << live.note;
  EXPECT_EQ(fs::path(live.record_path).parent_path(), records.path);
  EXPECT_TRUE(fs::exists(live.record_path));
}

TEST(TrainerLaunch, KeyboardRunWithoutRecordAndBadCasesAreRefused) {
  TrainerOptions options;
  options.box = BoxChoice::kNone;
  options.record = false;
  session::KeyboardInput keyboard;
  LiveSession live = open_live_session(options, ".", kCases + "/neuro_right_ica.case", false, keyboard);
  ASSERT_NE(live.session, nullptr) << live.error;
  EXPECT_TRUE(live.record_path.empty());
  // A case without a vessel surface (analytic tubes) and a missing file: no session, one line.
  const std::string analytic = std::string(CATHBOX_SOURCE_DIR) + "/tests/sim/tool/data/y_analytic.case";
  LiveSession tubes = open_live_session(options, ".", analytic, false, keyboard);
  EXPECT_EQ(tubes.session, nullptr);
  EXPECT_NE(tubes.error.find("needs a case with a vessel file"), std::string::npos) << tubes.error;
  TempDir dir;
  for (const std::string& path : {(dir.path / "missing.case").string(), std::string(CATHBOX_SOURCE_DIR) + "/README.md"}) {
    LiveSession bad = open_live_session(options, ".", path, false, keyboard);
    EXPECT_EQ(bad.session, nullptr) << path;
    EXPECT_FALSE(bad.error.empty()) << path;
    EXPECT_EQ(bad.error.find('\n'), std::string::npos) << bad.error;
  }
}

TEST(TrainerLaunch, ABoxPerToolOrTheKeyboardSayingWhy) {
  // Two emulators started for the run (real cathbox-emu processes beside the tests' programs).
  TrainerOptions options;
  options.record = false;
  options.boxes = {"catheter=emu", "guidewire=emu"};
  session::KeyboardInput keyboard;
  const std::string bin = std::string(CATHBOX_BINARY_DIR) + "/bin";
  LiveSession live = open_live_session(options, bin, kCases + "/neuro.case", false, keyboard);
  ASSERT_NE(live.session, nullptr) << live.error;
  const std::string hand = live.session->hand_description();
  EXPECT_EQ(hand.rfind("2 boxes: catheter <- serial EMU-0001", 0), 0u) << hand;
  EXPECT_NE(hand.find("guidewire <- serial EMU-0002"), std::string::npos) << hand;
  live.session.reset();
  // A tool the case does not have: the keyboard, and the reason in the hand's description.
  options.boxes = {"coil=emu", "guidewire=emu"};
  LiveSession bad = open_live_session(options, bin, kCases + "/neuro.case", false, keyboard);
  ASSERT_NE(bad.session, nullptr) << bad.error;
  EXPECT_EQ(bad.session->hand_description(),
            "keyboard (boxes: --box 'coil=emu': the case has no tool 'coil' (its tools: catheter, guidewire))");
}

// --script: the action script drives the run, its imaging verbs included; a bad one is one line
// naming its file and line.
TEST(TrainerLaunch, AScriptDrivesTheRunWithItsImagingVerbs) {
  TempDir dir;
  const std::string script = (dir.path / "angio.actions").string();
  std::ofstream(script) << "0 select catheter\n0 insert_to 60 at 100\n100 fluoro on\n300 inject 2 at 4\n1000 fluoro off\n1100 end\n";
  TrainerOptions options;
  options.record = false;
  options.script = script;
  session::KeyboardInput keyboard;
  LiveSession live = open_live_session(options, ".", kCases + "/neuro.case", true, keyboard);
  ASSERT_NE(live.session, nullptr) << live.error;
  EXPECT_EQ(live.session->hand_kind(), session::HandKind::kActionScript);
  while (!live.session->over()) live.session->step_virtual(1000);
  const session::Metrics& m = live.session->metrics();
  EXPECT_NEAR(*m.fluoroscopy_time_s, 0.9, 1e-9);
  EXPECT_NEAR(*m.contrast_volume_ml, 2.0, 1e-9);
  EXPECT_EQ(m.fluoroscopy_runs, 1);
  std::ofstream(script) << "0 carm 200 0\n";
  live = open_live_session(options, ".", kCases + "/neuro.case", true, keyboard);
  EXPECT_EQ(live.session, nullptr);
  EXPECT_EQ(live.error, script + ":1: carm: LAO/RAO angle must be within +-120 degrees");
}

}  // namespace
}  // namespace cathbox::app
