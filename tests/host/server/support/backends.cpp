#include "backends.hpp"

#include <stdlib.h>

#include <atomic>
#include <filesystem>
#include <mutex>

#include "server/migrations.hpp"
#include "server/testing/pg_cluster.hpp"

namespace cathbox::server::test {

namespace {

struct Shared {
  std::mutex mutex;
  std::unique_ptr<testing::PgCluster> cluster;
  std::vector<std::string> folders;
  std::atomic<int> counter{0};
  ~Shared() {
    cluster.reset();
    std::error_code ec;
    for (const std::string& f : folders) std::filesystem::remove_all(f, ec);
  }
};

Shared& shared() {
  static Shared s;
  return s;
}

testing::PgCluster& cluster() {
  Shared& s = shared();
  std::lock_guard lock(s.mutex);
  if (!s.cluster) {
    auto started = testing::PgCluster::start();
    if (!started) {
      ADD_FAILURE() << started.error().message;
      throw std::runtime_error(started.error().message);
    }
    s.cluster = std::move(started.value());
  }
  return *s.cluster;
}

}  // namespace

std::string temp_folder() {
  char templ[] = "/tmp/cathbox-test-XXXXXX";
  if (::mkdtemp(templ) == nullptr) throw std::runtime_error("mkdtemp failed");
  std::lock_guard lock(shared().mutex);
  shared().folders.emplace_back(templ);
  return templ;
}

std::string fresh_database_url(const std::string& backend) {
  const int n = ++shared().counter;
  if (backend == "sqlite") return "sqlite:" + temp_folder() + "/cathbox.db";
  testing::PgCluster& c = cluster();
  const std::string name = "t" + std::to_string(n);
  const Status made = c.create_database(name);
  if (!made) throw std::runtime_error(made.error().message);
  return c.url(name);
}

std::unique_ptr<Database> fresh_database(const std::string& backend) {
  DatabaseOpen opened = open_database(fresh_database_url(backend));
  if (!opened.db) throw std::runtime_error(opened.error);
  return std::move(opened.db);
}

std::unique_ptr<Store> fresh_store(const std::string& backend) {
  std::unique_ptr<Database> db = fresh_database(backend);
  const auto migrated = migrate(*db);
  if (!migrated) throw std::runtime_error(migrated.error().message);
  return std::make_unique<Store>(std::move(db));
}

void stop_postgres(const std::string& mode) {
  const Status s = cluster().stop(mode);
  if (!s) throw std::runtime_error(s.error().message);
}

void start_postgres() {
  const Status s = cluster().start_again();
  if (!s) throw std::runtime_error(s.error().message);
}

}  // namespace cathbox::server::test
