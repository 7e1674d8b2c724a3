#include "server/server_app.hpp"

namespace cathbox::server {

Result<std::unique_ptr<ServerApp>> ServerApp::start(ServerConfig config) {
  std::unique_ptr<ServerApp> app(new ServerApp());
  Result<std::unique_ptr<ServerCore>> core = ServerCore::open(config);
  if (!core) return core.error();
  app->core_ = std::move(core.value());
  app->maintenance_every_s_ = config.maintenance_every_s;
  app->failure_window_us_ = config.auth.failure_window_us;
  app->http_ = std::make_unique<HttpServer>(app->core_->api(), app->core_->hub(), config.http);
  Result<std::uint16_t> port = app->http_->start();
  if (!port) return port.error();  // 400 bad options (address, TLS files), 503 address unavailable
  app->port_ = port.value();
  ServerApp* raw = app.get();
  if (app->maintenance_every_s_ > 0) app->maintenance_ = std::thread([raw] { raw->maintain(); });
  return app;
}

void ServerApp::maintain() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, std::chrono::seconds(maintenance_every_s_), [&] { return stopping_; });
    if (stopping_) break;
    lock.unlock();
    maintain_once();
    lock.lock();
  }
}

void ServerApp::maintain_once() {
  try {
    const std::int64_t now = core_->clock().now_us();
    (void)core_->store().purge_tokens(now);
    (void)core_->store().purge_login_failures(now - failure_window_us_);
    (void)core_->enforce_retention();
  } catch (const std::exception&) {
    // The database is away; try again next time.
  }
}

void ServerApp::stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  wake_.notify_all();
  if (maintenance_.joinable()) maintenance_.join();
  if (http_) http_->stop();
}

ServerApp::~ServerApp() { stop(); }

std::string ServerApp::describe_db() const { return core_->store().database().describe(); }

}  // namespace cathbox::server
