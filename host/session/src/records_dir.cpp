#include "session/records_dir.hpp"

#include <cctype>
#include <cstdlib>
#include <ctime>
#include <filesystem>

namespace cathbox::session {

std::string user_dir(UserDir kind, const std::string& relative) {
  const char* variable = kind == UserDir::kData ? "XDG_DATA_HOME" : kind == UserDir::kCache ? "XDG_CACHE_HOME" : "XDG_CONFIG_HOME";
  const char* fallback = kind == UserDir::kData ? "/.local/share" : kind == UserDir::kCache ? "/.cache" : "/.config";
  const char* xdg = std::getenv(variable);
  if (xdg != nullptr && xdg[0] == '/') return std::string(xdg) + "/cathbox/" + relative;
  const char* home = std::getenv("HOME");
  return std::string(home != nullptr && home[0] != '\0' ? home : ".") + fallback + "/cathbox/" + relative;
}

std::string records_dir() { return user_dir(UserDir::kData, "records"); }

base::Result<std::string> new_record_path(const std::string& dir, const std::string& case_name) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return base::Error{dir + ": cannot create the records folder: " + ec.message()};
  std::string slug;
  for (const char c : case_name) {
    if (std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_') {
      slug += c;
    } else if (!slug.empty() && slug.back() != '_') {
      slug += '_';
    }
    if (slug.size() >= 48) break;
  }
  while (!slug.empty() && slug.back() == '_') slug.pop_back();
  if (slug.empty()) slug = "run";
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &local);
  const std::string base = dir + "/" + stamp + "-" + slug;
  std::string path = base + ".cbxrec";
  for (int n = 2; std::filesystem::exists(path, ec); ++n) path = base + "-" + std::to_string(n) + ".cbxrec";
  return path;
}

}  // namespace cathbox::session
