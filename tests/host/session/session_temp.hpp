#pragma once
// A path under the build tree for a session test's record (the folder is created).
#include <filesystem>
#include <string>

namespace cathbox::session::testing {

inline std::string temp_path(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(CATHBOX_BINARY_DIR) / "session_test";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

}  // namespace cathbox::session::testing
