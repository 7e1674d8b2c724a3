#pragma once
// What the session tests share: a scratch path below the build tree, a bundled case, and an
// action-script hand from script text.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "session/action_script_hand.hpp"
#include "session/session_case.hpp"
#include "scenario/action_script.hpp"

namespace cathbox::session::fixtures {

// CATHBOX_BINARY_DIR/<dir>/<name>, the folder created.
inline std::string temp_path(const std::string& dir, const std::string& name) {
  const std::filesystem::path d = std::filesystem::path(CATHBOX_BINARY_DIR) / dir;
  std::filesystem::create_directories(d);
  return (d / name).string();
}

inline std::string case_path(const std::string& file) { return std::string(CATHBOX_SOURCE_DIR) + "/cases/" + file; }

// A bundled case (cases/<file>), loaded as every front end loads it.
inline std::unique_ptr<SessionCase> load(const std::string& file) {
  SessionCaseLoad loaded = load_session_case(case_path(file));
  EXPECT_TRUE(loaded) << loaded.error().message;
  return std::move(loaded.value());
}

// An action-script hand playing `text` ("test.actions") against the case's tools.
inline std::unique_ptr<Hand> script_hand(const SessionCase& scene, const std::string& text) {
  const tool::ScriptParse parsed = tool::parse_script(text, "test.actions");
  EXPECT_TRUE(parsed) << (parsed ? "" : parsed.error().message);
  if (!parsed) return nullptr;
  std::string error;
  auto hand = ActionScriptHand::make(*parsed, "test.actions", ActionScriptHand::tool_infos(scene), 0);
  EXPECT_TRUE(hand) << (hand ? "" : hand.error().message);
  if (!hand) return nullptr;
  return std::move(*hand);
}

}  // namespace cathbox::session::fixtures
