#include "pg_database.hpp"

#include "connection_pool.hpp"

#include <chrono>
#include <regex>
#include <thread>
#include <vector>

#include <pqxx/pqxx>

namespace cathbox::server {
namespace {

// A parameter as libpqxx sends it: text, or NULL. Blobs go as bytea's hex text form, so every
// value type travels the same way and the statement never needs a cast.
struct PgParam {
  std::optional<std::string> text;
};

PgParam to_param(const SqlValue& v) {
  if (std::holds_alternative<std::nullptr_t>(v)) return {};
  if (const auto* n = std::get_if<std::int64_t>(&v)) return {std::to_string(*n)};
  if (const auto* d = std::get_if<double>(&v)) return {sql_double_text(*d)};
  if (const auto* s = std::get_if<std::string>(&v)) {
    if (s->find('\0') != std::string::npos) {
      throw StoreError(StoreError::Kind::kInternal, "text parameter holds a NUL byte (inputs must reject these)");
    }
    return {*s};
  }
  static constexpr char kHex[] = "0123456789abcdef";
  const std::string& bytes = std::get<Blob>(v).bytes;
  std::string hex;
  hex.reserve(2 + 2 * bytes.size());
  hex += "\\x";
  for (const char ch : bytes) {
    const auto b = static_cast<unsigned char>(ch);
    hex += kHex[b >> 4];
    hex += kHex[b & 15];
  }
  return {std::move(hex)};
}

}  // namespace
}  // namespace cathbox::server

namespace pqxx {
template <>
struct string_traits<cathbox::server::PgParam> {
  static constexpr const char* name() noexcept { return "cathbox::server::PgParam"; }
  static constexpr bool has_null() noexcept { return true; }
  static bool is_null(const cathbox::server::PgParam& p) { return !p.text.has_value(); }
  static cathbox::server::PgParam null() { return {}; }
  static void from_string(const char str[], cathbox::server::PgParam& p) { p.text = str; }
  static std::string to_string(const cathbox::server::PgParam& p) { return p.text.value_or(std::string()); }
};
}  // namespace pqxx

namespace cathbox::server {
namespace {

constexpr pqxx::oid kInt2 = 21, kInt4 = 23, kInt8 = 20, kFloat4 = 700, kFloat8 = 701, kNumeric = 1700, kBytea = 17,
                    kBool = 16;

class PgSession final : public SqlSession {
 public:
  explicit PgSession(pqxx::transaction_base& tx) : tx_(tx) {}
  [[nodiscard]] SqlDialect dialect() const override { return SqlDialect::kPostgresql; }

  std::vector<SqlRow> query(std::string_view sql, const std::vector<SqlValue>& params) override {
    std::vector<PgParam> values;
    values.reserve(params.size());
    for (const SqlValue& v : params) values.push_back(to_param(v));
    const pqxx::result r = tx_.exec_params(std::string(sql), pqxx::prepare::make_dynamic_params(values));
    std::vector<SqlRow> rows;
    rows.reserve(r.size());
    const auto columns = static_cast<std::size_t>(r.columns());
    std::vector<pqxx::oid> types(columns);
    for (std::size_t c = 0; c < columns; ++c) types[c] = r.column_type(static_cast<pqxx::row::size_type>(c));
    for (const pqxx::row& row : r) {
      std::vector<SqlValue> fields;
      fields.reserve(columns);
      for (std::size_t c = 0; c < columns; ++c) {
        const pqxx::field f = row[static_cast<pqxx::row::size_type>(c)];
        if (f.is_null()) {
          fields.emplace_back(nullptr);
        } else if (types[c] == kInt2 || types[c] == kInt4 || types[c] == kInt8) {
          fields.emplace_back(f.as<std::int64_t>());
        } else if (types[c] == kFloat4 || types[c] == kFloat8 || types[c] == kNumeric) {
          fields.emplace_back(f.as<double>());
        } else if (types[c] == kBool) {
          fields.emplace_back(static_cast<std::int64_t>(f.as<bool>() ? 1 : 0));
        } else if (types[c] == kBytea) {
          const pqxx::binarystring b(f);
          fields.emplace_back(Blob{b.str()});
        } else {
          fields.emplace_back(std::string(f.c_str(), f.size()));
        }
      }
      rows.emplace_back(std::move(fields));
    }
    return rows;
  }

  void run_script(std::string_view sql) override { tx_.exec(std::string(sql)); }

 private:
  pqxx::transaction_base& tx_;
};

// SQLSTATE classes after which the connection is not worth keeping: 08 connection exception,
// 57 operator intervention (admin shutdown, crash shutdown, cannot connect now).
bool connection_lost(const std::string& sqlstate) {
  return sqlstate.rfind("08", 0) == 0 || sqlstate.rfind("57", 0) == 0;
}
// 40 transaction rollback (serialization failure, deadlock): run the transaction again. 23505
// unique violation: two transactions raced for the same next number (a case version); run
// again, the second now sees the first's row.
bool transient(const std::string& sqlstate) { return sqlstate.rfind("40", 0) == 0 || sqlstate == "23505"; }

class PgDatabase final : public Database {
 public:
  PgDatabase(std::string url, const DatabaseOptions& options)
      : url_(std::move(url)), options_(options), pool_(options.pool_size, [this] { return std::make_unique<pqxx::connection>(url_); }) {}

  [[nodiscard]] SqlDialect dialect() const override { return SqlDialect::kPostgresql; }
  [[nodiscard]] std::string describe() const override { return redact_pg_url(url_); }
  [[nodiscard]] PoolStats pool_stats() const override { return pool_.stats(); }

  std::string open_first() {
    try {
      pool_.open_first();
    } catch (const std::exception& e) {
      return redact_pg_url(url_) + ": " + one_line(e.what());
    }
    return {};
  }

  void transact(TxMode mode, const std::function<void(SqlSession&)>& work) override {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::milliseconds(options_.retry_ms);
    auto backoff = std::chrono::milliseconds(20);
    std::string last_error;
    for (;;) {
      std::unique_ptr<pqxx::connection> c;
      bool broken = false;
      try {
        c = pool_.acquire();
        {
          std::unique_ptr<pqxx::transaction_base> tx;
          if (mode == TxMode::kRead) {
            tx = std::make_unique<pqxx::read_transaction>(*c);
          } else {
            tx = std::make_unique<pqxx::work>(*c);
          }
          PgSession session(*tx);
          work(session);
          tx->commit();
        }
        pool_.release(std::move(c));
        return;
      } catch (const pqxx::in_doubt_error& e) {
        pool_.discard();
        throw StoreError(StoreError::Kind::kUnavailable, "postgresql: connection lost during commit (outcome unknown): " + one_line(e.what()));
      } catch (const pqxx::broken_connection& e) {
        broken = true;
        last_error = one_line(e.what());
      } catch (const pqxx::sql_error& e) {
        if (connection_lost(e.sqlstate())) {
          broken = true;
        } else if (!transient(e.sqlstate())) {
          pool_.release(std::move(c));
          throw StoreError(StoreError::Kind::kInternal, "postgresql: " + one_line(e.what()));
        }
        last_error = one_line(e.what());
      } catch (const pqxx::failure& e) {
        // Other libpqxx failures come from a connection in a bad state.
        broken = true;
        last_error = one_line(e.what());
      } catch (...) {
        if (c) pool_.release(std::move(c));
        throw;
      }
      if (broken) {
        if (c) pool_.discard();
      } else if (c) {
        pool_.release(std::move(c));
      }
      if (Clock::now() + backoff > deadline) {
        throw StoreError(StoreError::Kind::kUnavailable, "postgresql unavailable: " + last_error);
      }
      std::this_thread::sleep_for(backoff);
      backoff = std::min(backoff * 2, std::chrono::milliseconds(400));
    }
  }

 private:
  static std::string one_line(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    for (char& ch : s) {
      if (ch == '\n' || ch == '\r') ch = ' ';
    }
    return s;
  }

  std::string url_;
  DatabaseOptions options_;
  ConnectionPool<pqxx::connection> pool_;
};

}  // namespace

std::string redact_pg_url(const std::string& url) {
  // postgresql://user:secret@host/db -> postgresql://user:***@host/db; password=... -> password=***
  static const std::regex userinfo(R"(^(postgres(?:ql)?://[^:/@?]*):[^@/?]*@)");
  static const std::regex keyword(R"(password=[^&\s]*)");
  std::string out = std::regex_replace(url, userinfo, "$1:***@");
  return std::regex_replace(out, keyword, "password=***");
}

DatabaseOpen open_pg_database(const std::string& url, const DatabaseOptions& options) {
  DatabaseOpen out;
  auto db = std::make_unique<PgDatabase>(url, options);
  out.error = db->open_first();
  if (out.error.empty()) out.db = std::move(db);
  return out;
}

}  // namespace cathbox::server
