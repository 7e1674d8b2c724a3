// Builds without host/session: the server runs, record uploads answer 503.
#include "server/server_app.hpp"

namespace cathbox::server {

std::unique_ptr<RecordChecker> make_session_checker() { return nullptr; }

}  // namespace cathbox::server
