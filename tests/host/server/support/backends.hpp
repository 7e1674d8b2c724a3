#pragma once
// The two databases every server test runs against: a fresh SQLite file in a temporary folder,
// or a fresh database in one real PostgreSQL cluster started (lazily, once per test program)
// by server::testing::PgCluster and stopped when the program ends.
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "server/sql.hpp"
#include "server/store.hpp"

namespace cathbox::server::test {

inline const std::vector<std::string> kBackends = {"sqlite", "postgresql"};

// A URL for a new, empty database of the given backend (each call a new one).
[[nodiscard]] std::string fresh_database_url(const std::string& backend);
// Opens it (fails the test on error).
[[nodiscard]] std::unique_ptr<Database> fresh_database(const std::string& backend);
// A migrated Store on a fresh database.
[[nodiscard]] std::unique_ptr<Store> fresh_store(const std::string& backend);
// The shared cluster's restart hooks (PostgreSQL only).
void stop_postgres(const std::string& mode);
void start_postgres();
// A new temporary folder, removed when the program ends.
[[nodiscard]] std::string temp_folder();

// For INSTANTIATE_TEST_SUITE_P(..., testing::ValuesIn(kBackends), BackendName).
struct BackendName {
  std::string operator()(const ::testing::TestParamInfo<std::string>& info) const { return info.param; }
};

}  // namespace cathbox::server::test
