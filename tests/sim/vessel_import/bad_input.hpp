#pragma once
// The bad-input cases of the text readers: a name, the text, and the line and message its first
// error must give (file:line: message).
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "vessel_import/import_error.hpp"

namespace cathbox::vessel_import::test {

struct BadInput {
  const char* name;
  std::string text;
  int line;
  const char* message;
};

inline std::string case_name(const ::testing::TestParamInfo<BadInput>& p) { return p.param.name; }

inline void expect_first_error(const std::vector<ImportError>& errors, const std::string& file, const BadInput& bad) {
  ASSERT_FALSE(errors.empty());
  const ImportError& e = errors.front();
  EXPECT_EQ(e.line, bad.line) << e.to_string();
  EXPECT_NE(e.to_string().find(bad.message), std::string::npos) << e.to_string();
  EXPECT_EQ(e.to_string().rfind(file + ":", 0), 0u) << e.to_string();
}

}  // namespace cathbox::vessel_import::test
