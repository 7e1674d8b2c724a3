#include "app/trainer_settings.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "server/json_input.hpp"
#include "session/records_dir.hpp"

namespace cathbox::app {

std::string trainer_settings_path() { return session::user_dir(session::UserDir::kConfig, "trainer.json"); }

base::Status<> apply_trainer_settings(TrainerOptions& options) {
  const bool explicit_file = !options.settings_file.empty();
  const std::string path = explicit_file ? options.settings_file : trainer_settings_path();
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (!explicit_file) return base::Ok{};  // no settings: the command line alone
    return base::Error{path + ": cannot read the settings file"};
  }
  std::ostringstream text;
  text << in.rdbuf();
  server::Result<nlohmann::json> parsed = server::parse_json_object(text.str(), path);
  if (!parsed) return base::Error{parsed.error().message};
  server::FieldReader f(parsed.value());
  f.only({"server", "user", "password_file", "rig"});
  const std::optional<std::string> url = f.optional_string("server", 256);
  const std::optional<std::string> user = f.optional_string("user", 64);
  const std::optional<std::string> password_file = f.optional_string("password_file", 4096);
  const std::optional<std::string> rig = f.optional_string("rig", 64);
  if (f.ok() && url && !url->starts_with("http://") && !url->starts_with("https://")) {
    f.fail("server", "expected a URL https://HOST:PORT or http://HOST:PORT");
  }
  if (!f.ok()) return base::Error{path + ": " + f.error().message};
  if (options.server_url.empty() && url) options.server_url = *url;
  if (options.server_user.empty() && user) options.server_user = *user;
  if (options.password_file.empty() && password_file) options.password_file = *password_file;
  if (options.rig.empty() && rig) options.rig = *rig;
  return base::Ok{};
}

base::Result<ServerLinkOptions> server_link_options(const TrainerOptions& options) {
  ServerLinkOptions out;
  out.url = options.server_url;
  out.user = options.server_user;
  out.rig = options.rig;
  out.ca_file = options.ca_file;
  if (out.user.empty()) return base::Error{"--server needs --user NAME (or \"user\" in the settings file)"};
  if (!options.password_file.empty()) {
    std::ifstream in(options.password_file);
    if (!in || !std::getline(in, out.password)) return base::Error{options.password_file + ": cannot read the password"};
    if (!out.password.empty() && out.password.back() == '\r') out.password.pop_back();
  } else if (const char* env = std::getenv("CATHBOX_PASSWORD"); env != nullptr) {
    out.password = env;
  }
  if (out.password.empty()) return base::Error{"--server needs a password: --password-file FILE or $CATHBOX_PASSWORD"};
  return out;
}

}  // namespace cathbox::app
