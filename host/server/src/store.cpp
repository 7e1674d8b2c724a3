// The Store's users, their tokens and login failures (the Store's other tables: store_cases.cpp,
// store_results.cpp).
#include "server/store.hpp"

#include "store_rows.hpp"

namespace cathbox::server {

using store_rows::I;
using store_rows::kUserColumns;
using store_rows::read_all;
using store_rows::read_one;
using store_rows::read_user;

namespace {

// Every login failure of the account `name`, from any address (keys "NAME@ADDRESS").
void delete_account_login_failures(SqlSession& s, const std::string& name) {
  std::string pattern;
  for (const char c : name) {
    if (c == '%' || c == '_' || c == '\\') pattern += '\\';
    pattern += c;
  }
  pattern += "@%";
  (void)s.query("DELETE FROM login_failures WHERE name = $1 OR name LIKE $2 ESCAPE '\\'", {name, pattern});
}

}  // namespace

// ---- users -------------------------------------------------------------------------------

std::optional<User> Store::create_user(const std::string& name, Role role, const std::string& password_hash, I now_us) {
  std::optional<User> out;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    const auto row = s.query_one(
        std::string("INSERT INTO users (name, role, password_hash, disabled, created_us) VALUES ($1, $2, $3, 0, $4) "
                    "ON CONFLICT (name) DO NOTHING RETURNING ") + kUserColumns,
        {name, std::string(role_name(role)), password_hash, now_us});
    if (row) out = read_user(*row);
  });
  return out;
}

std::optional<User> Store::user_by_name(const std::string& name) {
  return read_one(*db_, std::string("SELECT ") + kUserColumns + " FROM users WHERE name = $1", {name}, read_user);
}

std::optional<User> Store::user_by_id(I id) {
  return read_one(*db_, std::string("SELECT ") + kUserColumns + " FROM users WHERE id = $1", {id}, read_user);
}

std::vector<User> Store::list_users() {
  return read_all(*db_, std::string("SELECT ") + kUserColumns + " FROM users ORDER BY name", {}, read_user);
}

int Store::count_admins() {
  int n = 0;
  db_->transact(TxMode::kRead, [&](SqlSession& s) {
    n = static_cast<int>(s.query_one("SELECT COUNT(*) FROM users WHERE role = 'admin' AND disabled = 0")->integer(0));
  });
  return n;
}

bool Store::update_user(I id, std::optional<Role> role, std::optional<std::string> password_hash, std::optional<bool> disabled) {
  return update_user_keeping_an_admin(id, role, std::move(password_hash), disabled, false) == UserUpdate::kDone;
}

Store::UserUpdate Store::update_user_keeping_an_admin(I id, std::optional<Role> role, std::optional<std::string> password_hash,
                                                      std::optional<bool> disabled, bool keep_an_admin) {
  UserUpdate outcome = UserUpdate::kNotFound;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    outcome = UserUpdate::kNotFound;
    const std::optional<SqlRow> row = s.query_one("SELECT role, disabled FROM users WHERE id = $1", {id});
    if (!row) return;
    const bool active_admin = row->text(0) == "admin" && row->integer(1) == 0;
    const bool loses_admin = active_admin && ((role && *role != Role::kAdmin) || disabled.value_or(false));
    if (keep_an_admin && loses_admin) {
      // The count and the change in one transaction: two admins demoting each other at once
      // cannot both see the other still an admin (PostgreSQL: the admins' rows are locked;
      // SQLite: write transactions run one at a time).
      const char* others = s.dialect() == SqlDialect::kPostgresql
                               ? "SELECT id FROM users WHERE role = 'admin' AND disabled = 0 AND id <> $1 FOR UPDATE"
                               : "SELECT id FROM users WHERE role = 'admin' AND disabled = 0 AND id <> $1";
      if (s.query(others, {id}).empty()) {
        outcome = UserUpdate::kLastAdmin;
        return;
      }
    }
    outcome = UserUpdate::kDone;
    if (role) (void)s.query("UPDATE users SET role = $1 WHERE id = $2", {std::string(role_name(*role)), id});
    if (password_hash) (void)s.query("UPDATE users SET password_hash = $1 WHERE id = $2", {*password_hash, id});
    if (disabled) (void)s.query("UPDATE users SET disabled = $1 WHERE id = $2", {I{*disabled ? 1 : 0}, id});
  });
  return outcome;
}

// ---- tokens --------------------------------------------------------------------------------

void Store::insert_token(const std::string& token_hash, I user_id, I issued_us, I expires_us) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    (void)s.query("INSERT INTO tokens (token_hash, user_id, issued_us, expires_us) VALUES ($1, $2, $3, $4)",
                  {token_hash, user_id, issued_us, expires_us});
  });
}

std::optional<TokenOwner> Store::token_owner(const std::string& token_hash) {
  std::optional<TokenOwner> out;
  db_->transact(TxMode::kRead, [&](SqlSession& s) {
    const auto row = s.query_one(
        "SELECT u.id, u.name, u.role, u.password_hash, u.disabled, u.created_us, t.expires_us "
        "FROM tokens t JOIN users u ON u.id = t.user_id WHERE t.token_hash = $1",
        {token_hash});
    if (row) out = TokenOwner{read_user(*row), row->integer(6)};
  });
  return out;
}

void Store::delete_token(const std::string& token_hash) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) { (void)s.query("DELETE FROM tokens WHERE token_hash = $1", {token_hash}); });
}

void Store::delete_user_tokens(I user_id) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) { (void)s.query("DELETE FROM tokens WHERE user_id = $1", {user_id}); });
}

int Store::purge_tokens(I now_us) {
  int n = 0;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    n = static_cast<int>(s.query("DELETE FROM tokens WHERE expires_us <= $1 RETURNING 1", {now_us}).size());
  });
  return n;
}

// ---- login failures ------------------------------------------------------------------------

void Store::record_login_failure(const std::string& name, I at_us) {
  db_->transact(TxMode::kWrite,
                [&](SqlSession& s) { (void)s.query("INSERT INTO login_failures (name, at_us) VALUES ($1, $2)", {name, at_us}); });
}

int Store::login_failures_since(const std::string& name, I since_us) {
  int n = 0;
  db_->transact(TxMode::kRead, [&](SqlSession& s) {
    n = static_cast<int>(s.query_one("SELECT COUNT(*) FROM login_failures WHERE name = $1 AND at_us >= $2", {name, since_us})->integer(0));
  });
  return n;
}

void Store::clear_login_failures(const std::string& name) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) { (void)s.query("DELETE FROM login_failures WHERE name = $1", {name}); });
}

void Store::clear_account_login_failures(const std::string& name) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    delete_account_login_failures(s, name);
  });
}

int Store::purge_login_failures(I before_us) {
  int n = 0;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    n = static_cast<int>(s.query("DELETE FROM login_failures WHERE at_us < $1 RETURNING 1", {before_us}).size());
  });
  return n;
}

std::optional<std::vector<std::string>> Store::delete_user(I id) {
  std::optional<std::vector<std::string>> hashes;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    hashes.reset();
    const std::optional<SqlRow> user = s.query_one("SELECT name FROM users WHERE id = $1", {id});
    if (!user) return;
    const std::string name = user->text(0);
    hashes.emplace();
    for (const SqlRow& r : s.query("SELECT content_hash FROM results WHERE user_id = $1", {id})) hashes->push_back(r.text(0));
    // Results, records, metrics, assignments for them, tokens and live rigs go by ON DELETE CASCADE.
    (void)s.query("DELETE FROM users WHERE id = $1", {id});
    delete_account_login_failures(s, name);
  });
  return hashes;
}

}  // namespace cathbox::server
