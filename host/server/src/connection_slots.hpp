#pragma once
// Counted shares of the server's resources, held for as long as a connection or a WebSocket
// lives: the open connections, each client address's connections, each account's WebSockets.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <unordered_map>

#include "http_server_impl.hpp"

namespace cathbox::server {

// Counts a connection for as long as it lives.
struct ConnectionSlot {
  std::atomic<std::size_t>* counter;
  explicit ConnectionSlot(std::atomic<std::size_t>& c) : counter(&c) { ++c; }
  ConnectionSlot(const ConnectionSlot&) = delete;
  ConnectionSlot& operator=(const ConnectionSlot&) = delete;
  ~ConnectionSlot() { --*counter; }
};

// A share of a counted resource, for as long as its holder lives: taken() is false when `key`
// already held `limit` of them. The counts live in `counts` under `mutex`.
template <class Key>
class CountedSlot {
 public:
  CountedSlot(std::mutex& mutex, std::unordered_map<Key, std::size_t>& counts, Key key, std::size_t limit)
      : mutex_(&mutex), counts_(&counts), key_(std::move(key)) {
    std::lock_guard lock(*mutex_);
    std::size_t& n = (*counts_)[key_];
    taken_ = n < limit;
    if (taken_) ++n;
    else if (n == 0) counts_->erase(key_);
  }
  CountedSlot(const CountedSlot&) = delete;
  CountedSlot& operator=(const CountedSlot&) = delete;
  ~CountedSlot() {
    if (!taken_) return;
    std::lock_guard lock(*mutex_);
    const auto it = counts_->find(key_);
    if (it != counts_->end() && --it->second == 0) counts_->erase(it);
  }
  [[nodiscard]] bool taken() const { return taken_; }
  [[nodiscard]] const Key& key() const { return key_; }

 private:
  std::mutex* mutex_;
  std::unordered_map<Key, std::size_t>* counts_;
  Key key_;
  bool taken_ = false;
};

// One client address's share of the connections, for as long as a connection lives (moved from
// the HTTP session into the WebSocket one on an upgrade); not taken when the address already had
// max_connections_per_address open: the connection is then closed at once.
class AddressSlot : public CountedSlot<std::string> {
 public:
  AddressSlot(HttpServer::Impl& s, std::string address)
      : CountedSlot(s.per_address_mutex, s.per_address, std::move(address), s.options.max_connections_per_address) {}
  [[nodiscard]] const std::string& address() const { return key(); }
};

// One account's share of the WebSockets, for as long as one lives; not taken when the account
// already holds max_websockets_per_account (the upgrade is then refused with 429).
class AccountSlot : public CountedSlot<std::int64_t> {
 public:
  AccountSlot(HttpServer::Impl& s, std::int64_t user_id)
      : CountedSlot(s.ws_mutex, s.ws_per_account, user_id, s.options.max_websockets_per_account) {}
};

}  // namespace cathbox::server
