#pragma once
// A real session record for the server's tests: the y-bifurcation's left branch driven by its
// action script, recorded in virtual time to `path` (tests that link cathbox_session).
#include <string>

#include <gtest/gtest.h>

#include "session/action_script_hand.hpp"
#include "session/session.hpp"

namespace cathbox::server::test {

inline std::string record_left_branch_to(const std::string& path) {
  auto scene = session::load_session_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.case");
  EXPECT_TRUE(scene.value) << scene.error;
  std::string error;
  auto hand = session::ActionScriptHand::load(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation_left.actions",
                                              *scene.value, error);
  EXPECT_TRUE(hand) << error;
  session::Session s(std::move(scene.value), std::move(hand));
  EXPECT_TRUE(s.record_to(path, error)) << error;
  while (!s.over()) s.step_virtual(1000);
  EXPECT_TRUE(s.recorder()->close());
  return path;
}

}  // namespace cathbox::server::test
