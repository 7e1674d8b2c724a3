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

}  // namespace cathbox::server
