#include "server/server_app.hpp"

#include "server/audit_log.hpp"
#include "server/iso_time.hpp"
#include "server/migrations.hpp"
#include "server/sha256.hpp"

namespace cathbox::server {

Result<std::unique_ptr<ServerCore>> ServerCore::open(ServerConfig& config) {
  std::unique_ptr<ServerCore> core(new ServerCore());
  core->clock_ = config.clock != nullptr ? config.clock : &core->system_clock_;
  core->instance_ = config.instance.empty() ? random_token(6) : config.instance;
  if (config.record_retention_days < 0) return make_error(400, "--record-retention-days: expected 0 (keep) or more days");
  core->record_retention_days_ = config.record_retention_days;
  DatabaseOpen opened = open_database(config.db_url, config.database);
  if (!opened.db) return make_error(opened.error.rfind("--db: unknown", 0) == 0 ? 400 : 503, opened.error);
  const bool postgres = opened.db->dialect() == SqlDialect::kPostgresql;
  Result<MigrationReport> migrated = make_error(503, "not migrated");
  try {
    migrated = migrate(*opened.db);
  } catch (const StoreError& e) {
    return make_error(503, std::string("migrating the database: ") + e.what());
  }
  if (!migrated) return migrated.error();
  core->schema_version_ = migrated.value().to_version;
  core->store_ = std::make_unique<Store>(std::move(opened.db));
  core->auth_ = std::make_unique<Auth>(*core->store_, *core->clock_, PasswordHasher(config.argon2), config.auth);
  core->cases_ = std::make_unique<CaseLibrary>(*core->store_);
  LiveBus* bus = nullptr;
  if (postgres) {
    Result<std::unique_ptr<PgLiveBus>> pg = PgLiveBus::start(config.db_url, core->hub_, *core->store_, *core->clock_, core->instance_);
    if (!pg) return pg.error();
    core->pg_bus_ = std::move(pg.value());
    bus = core->pg_bus_.get();
  } else {
    core->local_bus_ = std::make_unique<LocalLiveBus>(core->hub_);
    bus = core->local_bus_.get();
  }
  core->live_ = std::make_unique<LiveService>(*core->store_, *core->clock_, *bus, core->instance_, config.live);
  core->checker_ = config.checker ? std::move(config.checker) : make_session_checker();
  if (!config.cache_dir.empty()) core->cache_.keep_on_disk(config.cache_dir);
  core->api_ = std::make_unique<Api>(ApiContext{*core->store_, *core->clock_, *core->auth_, *core->cases_, *core->live_, core->checker_.get(), &core->cache_});
  return core;
}

int ServerCore::enforce_retention() {
  if (record_retention_days_ <= 0) return 0;
  constexpr std::int64_t kDayUs = 86'400'000'000;
  const std::int64_t now = clock_->now_us();
  const std::int64_t before = now - std::int64_t{record_retention_days_} * kDayUs;
  const std::vector<std::string> gone = store_->drop_records_uploaded_before(before, now);
  if (gone.empty()) return 0;
  for (const std::string& hash : gone) cache_.erase(trace_cache_key(hash));
  store_->database().scrub();
  append_audit(store_->database(), {0, now, "cathbox-server", "records.retention", "results",
                                    "records=" + std::to_string(gone.size()) + " uploaded_before=" + iso_time(before) +
                                        " days=" + std::to_string(record_retention_days_),
                                    "server"});
  return static_cast<int>(gone.size());
}

ServerCore::~ServerCore() {
  pg_bus_.reset();  // its threads use the store and the hub
}

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
