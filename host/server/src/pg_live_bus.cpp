#include "server/pg_live_bus.hpp"

#include <chrono>

#include <nlohmann/json.hpp>
#include <pqxx/pqxx>

namespace cathbox::server {

namespace {
constexpr const char* kChannel = "cathbox_live";
using namespace std::chrono_literals;
}  // namespace

struct PgLiveBus::Impl {
  std::string url;
  LiveHub& hub;
  Store& store;
  Clock& clock;
  std::string instance;

  mutable std::mutex mutex;
  std::condition_variable wake;
  std::deque<std::string> queue;  // payloads waiting to be NOTIFYed
  bool stopping = false;
  bool listening = false;
  std::condition_variable listening_changed;
  PgLiveBusStats stats;

  std::thread publisher;
  std::thread listener;

  Impl(std::string u, LiveHub& h, Store& s, Clock& c, std::string i)
      : url(std::move(u)), hub(h), store(s), clock(c), instance(std::move(i)) {}

  void enqueue(char kind, const std::string& rig, const LiveMessage& message) {
    std::string payload = instance + '\t' + kind + '\t' + rig + '\t' + *message;
    {
      std::lock_guard lock(mutex);
      if (queue.size() >= kMaxQueued) {
        queue.pop_front();
        ++stats.dropped;
      }
      queue.push_back(std::move(payload));
    }
    wake.notify_one();
  }

  // Sleeps up to `d` unless stopping; false when stopping.
  bool pause(std::chrono::milliseconds d) {
    std::unique_lock lock(mutex);
    wake.wait_for(lock, d, [&] { return stopping; });
    return !stopping;
  }

  void run_publisher() {
    std::unique_ptr<pqxx::connection> conn;
    auto backoff = 50ms;
    auto next_purge = std::chrono::steady_clock::now();
    for (;;) {
      std::vector<std::string> batch;
      {
        std::unique_lock lock(mutex);
        wake.wait_for(lock, 1s, [&] { return stopping || !queue.empty(); });
        if (stopping) return;
        std::size_t bytes = 0;
        while (!queue.empty() && batch.size() < 256 && bytes < 512 * 1024) {
          bytes += queue.front().size();
          batch.push_back(std::move(queue.front()));
          queue.pop_front();
        }
      }
      try {
        if (!conn) {
          conn = std::make_unique<pqxx::connection>(url);
          pqxx::nontransaction setup(*conn);
          setup.exec("SET synchronous_commit TO off");  // live frames need no durability
        }
        nlohmann::json payloads = nlohmann::json::array();
        for (std::string& p : batch) {
          if (p.size() > kMaxNotifyPayload) {
            const std::size_t header_end = p.find('\t', p.find('\t', p.find('\t') + 1) + 1);
            const std::int64_t id = store.insert_live_overflow(p.substr(header_end + 1), clock.now_us());
            p = p.substr(0, header_end + 1) + "@" + std::to_string(id);
            std::lock_guard lock(mutex);
            ++stats.overflowed;
          }
          payloads.push_back(std::move(p));
        }
        if (!payloads.empty()) {
          pqxx::nontransaction tx(*conn);
          tx.exec_params("SELECT pg_notify($1, p) FROM json_array_elements_text($2::json) AS p", kChannel, payloads.dump());
          std::lock_guard lock(mutex);
          stats.sent += payloads.size();
        }
        if (std::chrono::steady_clock::now() >= next_purge) {
          (void)store.purge_live_overflow(clock.now_us() - 60'000'000);
          next_purge = std::chrono::steady_clock::now() + 10s;
        }
        backoff = 50ms;
      } catch (const std::exception&) {
        // Database gone (or a StoreError from the overflow table): drop this batch, reconnect.
        conn.reset();
        {
          std::lock_guard lock(mutex);
          stats.dropped += batch.size();
          ++stats.reconnects;
        }
        if (!pause(backoff)) return;
        backoff = std::min(backoff * 2, std::chrono::milliseconds(1000));
      }
    }
  }

  void on_notification(const std::string& payload) {
    const std::size_t a = payload.find('\t');
    const std::size_t b = a == std::string::npos ? a : payload.find('\t', a + 1);
    const std::size_t c = b == std::string::npos ? b : payload.find('\t', b + 1);
    if (c == std::string::npos || b != a + 2) return;
    if (payload.compare(0, a, instance) == 0 && a == instance.size()) return;  // our own
    const char kind = payload[a + 1];
    const std::string rig = payload.substr(b + 1, c - b - 1);
    std::string message = payload.substr(c + 1);
    if (!message.empty() && message[0] == '@') {
      std::optional<std::string> stored;
      try {
        stored = store.live_overflow(std::stoll(message.substr(1)));
      } catch (const std::exception&) {
        return;
      }
      if (!stored) return;
      message = std::move(*stored);
    }
    {
      std::lock_guard lock(mutex);
      ++stats.received;
    }
    auto shared = std::make_shared<const std::string>(std::move(message));
    if (kind == 'F') {
      hub.deliver_frame(rig, shared);
    } else if (kind == 'E') {
      hub.deliver_event(shared);
    }
  }

  class Receiver final : public pqxx::notification_receiver {
   public:
    Receiver(pqxx::connection_base& c, Impl& impl) : pqxx::notification_receiver(c, kChannel), impl_(impl) {}
    void operator()(const std::string& payload, int) override { impl_.on_notification(payload); }

   private:
    Impl& impl_;
  };

  void set_listening(bool on) {
    {
      std::lock_guard lock(mutex);
      listening = on;
    }
    listening_changed.notify_all();
  }

  // Connects and LISTENs; throws on failure.
  std::pair<std::unique_ptr<pqxx::connection>, std::unique_ptr<Receiver>> listen() {
    auto conn = std::make_unique<pqxx::connection>(url);
    auto receiver = std::make_unique<Receiver>(*conn, *this);
    conn->get_notifs();  // issues the LISTEN now
    return {std::move(conn), std::move(receiver)};
  }

  void run_listener(std::unique_ptr<pqxx::connection> conn, std::unique_ptr<Receiver> receiver) {
    auto backoff = 50ms;
    for (;;) {
      {
        std::lock_guard lock(mutex);
        if (stopping) break;
      }
      try {
        if (!conn) {
          auto [c, r] = listen();
          conn = std::move(c);
          receiver = std::move(r);
          std::lock_guard lock(mutex);
          ++stats.reconnects;
        }
        set_listening(true);
        backoff = 50ms;
        conn->await_notification(0, 200'000);
      } catch (const std::exception&) {
        set_listening(false);
        receiver.reset();
        conn.reset();
        if (!pause(backoff)) break;
        backoff = std::min(backoff * 2, std::chrono::milliseconds(1000));
      }
    }
    receiver.reset();
    conn.reset();
  }
};

PgLiveBus::PgLiveBus(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Result<std::unique_ptr<PgLiveBus>> PgLiveBus::start(const std::string& url, LiveHub& hub, Store& store, Clock& clock,
                                                    std::string instance_id) {
  auto impl = std::make_unique<Impl>(url, hub, store, clock, std::move(instance_id));
  std::unique_ptr<pqxx::connection> conn;
  std::unique_ptr<Impl::Receiver> receiver;
  try {
    auto [c, r] = impl->listen();
    conn = std::move(c);
    receiver = std::move(r);
  } catch (const std::exception& e) {
    std::string what = e.what();
    while (!what.empty() && what.back() == '\n') what.pop_back();
    return make_error(503, "live bus: cannot LISTEN on the database: " + what);
  }
  Impl* raw = impl.get();
  impl->listening = true;
  impl->listener = std::thread([raw, c = std::move(conn), r = std::move(receiver)]() mutable { raw->run_listener(std::move(c), std::move(r)); });
  impl->publisher = std::thread([raw] { raw->run_publisher(); });
  return std::unique_ptr<PgLiveBus>(new PgLiveBus(std::move(impl)));
}

PgLiveBus::~PgLiveBus() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->wake.notify_all();
  if (impl_->publisher.joinable()) impl_->publisher.join();
  if (impl_->listener.joinable()) impl_->listener.join();
}

void PgLiveBus::publish_frame(const std::string& rig, const LiveMessage& message) {
  impl_->hub.deliver_frame(rig, message);
  impl_->enqueue('F', rig, message);
}

void PgLiveBus::publish_event(const LiveMessage& message) {
  impl_->hub.deliver_event(message);
  impl_->enqueue('E', "", message);
}

PgLiveBusStats PgLiveBus::stats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->stats;
}

bool PgLiveBus::wait_listening(int timeout_ms) {
  std::unique_lock lock(impl_->mutex);
  return impl_->listening_changed.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] { return impl_->listening; });
}

}  // namespace cathbox::server
