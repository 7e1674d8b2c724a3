#include "ws_session.hpp"

#include <deque>

#include <boost/asio/post.hpp>

#include "http_fields.hpp"
#include "server/json_input.hpp"
#include "server/live_schema.hpp"

namespace cathbox::server {

namespace {

class WsSession final : public LiveSubscriber, public SweptSocket, public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(HttpServer::Impl& s, std::unique_ptr<AddressSlot> address_slot, std::unique_ptr<AccountSlot> account_slot,
            TlsOrPlainStream&& stream, Caller caller, std::optional<Publisher> publisher, std::vector<std::string> watching,
            std::string first_message)
      : s_(s),
        address_slot_(std::move(address_slot)),
        account_slot_(std::move(account_slot)),
        ws_(std::move(stream)),
        caller_(std::move(caller)),
        publisher_(std::move(publisher)),
        watching_(std::move(watching)),
        first_message_(std::move(first_message)) {}

  void start(http::request<http::string_body> req) {
    beast::get_lowest_layer(ws_).expires_never();
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    // A browser, which cannot set Authorization on a WebSocket, offers the subprotocols
    // "cathbox, bearer.TOKEN": the answer names "cathbox" (never the token).
    const bool subprotocol = !bearer_from_subprotocols(sv(req[http::field::sec_websocket_protocol])).empty();
    ws_.set_option(websocket::stream_base::decorator([subprotocol](websocket::response_type& res) {
      res.set(http::field::server, "cathbox-server");
      if (subprotocol) res.set(http::field::sec_websocket_protocol, "cathbox");
    }));
    ws_.read_message_max(publisher_ ? kMaxFrameBytes : kMaxWatcherMessageBytes);
    // The socket's idle time counts from its upgrade (its first message in), and sweeps see it
    // from now: before the peer has the answer, so a sweep after the peer's handshake finds it
    // with that stamp, however late the accept's completion runs here.
    last_activity_us_ = now_us();
    next_recheck_us_ = last_activity_us_ + recheck_us();
    {
      std::lock_guard lock(s_.ws_mutex);
      std::erase_if(s_.ws_sockets, [](const std::weak_ptr<SweptSocket>& w) { return w.expired(); });
      s_.ws_sockets.push_back(shared_from_this());
    }
    auto self = shared_from_this();
    ws_.async_accept(req, [self](beast::error_code ec) { self->on_accept(ec); });
  }

  void deliver(const LiveMessage& message) override {
    net::post(ws_.get_executor(), [self = shared_from_this(), message] { self->enqueue(message); });
  }

  // On the server's clock (http_server.hpp): an idle socket closes; the token is checked again
  // every ws_recheck_s.
  // A sweep that comes while the handshake is still being answered is judged when it completes.
  void sweep(std::int64_t now_us) override {
    net::post(ws_.get_executor(), [self = shared_from_this(), now_us] {
      if (self->finished_) return;
      if (!self->accepted_) {
        self->swept_before_accept_us_ = now_us;
        return;
      }
      self->judge(now_us);
    });
  }

 private:
  // At the sweep's `now_us`: closes the socket when idle too long, else rechecks its token when due.
  void judge(std::int64_t now_us) {
    const std::int64_t idle_us = std::int64_t{s_.options.ws_idle_timeout_s} * 1'000'000;
    if (evictable_when_idle() && now_us - last_activity_us_ >= idle_us) {
      finish();
      ws_.async_close(websocket::close_reason(websocket::close_code::going_away, "idle"), [self = shared_from_this()](beast::error_code) {});
      return;
    }
    if (!rechecking_ && now_us >= next_recheck_us_) recheck();
  }

  void on_accept(beast::error_code ec) {
    if (ec) return finish();
    accepted_ = true;
    if (publisher_) {
      ++s_.publishers;
      ++s_.publishers_now;
    } else {
      ++s_.watchers;
      ++s_.watchers_now;
      if (can_supervise(caller_.role)) s_.hub.subscribe_events(shared_from_this());
      for (const std::string& rig : watching_) s_.hub.subscribe(rig, shared_from_this(), watch_restriction());
      enqueue(std::make_shared<const std::string>(first_message_));
    }
    if (swept_before_accept_us_ >= 0) {
      judge(swept_before_accept_us_);
      if (finished_) return;
    }
    read();
  }

  // A trainee watches a rig only while they stream it (the hub checks again on its events).
  [[nodiscard]] std::string watch_restriction() const { return can_supervise(caller_.role) ? std::string() : caller_.name; }

  [[nodiscard]] std::int64_t now_us() const { return s_.api.context().clock.now_us(); }
  [[nodiscard]] std::int64_t recheck_us() const { return std::int64_t{std::max(1, s_.options.ws_recheck_s)} * 1'000'000; }
  // Idle for ws_idle_timeout_s closes a stream that sends no frame, and a trainee's watcher that
  // watches no rig and says nothing; an instructor's watcher (rig events) and a watcher of rigs
  // stay however quiet the rigs are.
  [[nodiscard]] bool evictable_when_idle() const { return publisher_ || (watching_.empty() && !can_supervise(caller_.role)); }

  // Off the I/O thread: is the token still good (not logged out, expired, or its account
  // disabled)? If not, the socket is closed (policy violation) and its watching ends.
  void recheck() {
    rechecking_ = true;
    net::post(s_.api_pool, [self = shared_from_this()] {
      bool good = true;
      try {
        ApiContext& c = self->s_.api.context();
        const std::optional<TokenOwner> owner = c.store.token_owner(self->caller_.token_hash);
        good = owner && owner->expires_us > c.clock.now_us() && !owner->user.disabled;
      } catch (const std::exception&) {
        // The database is away: keep the socket until it can be asked.
      }
      net::post(self->ws_.get_executor(), [self, good] {
        self->rechecking_ = false;
        self->next_recheck_us_ = self->now_us() + self->recheck_us();
        if (self->finished_ || good) return;
        self->finish();
        self->ws_.async_close(websocket::close_reason(websocket::close_code::policy_error, "token revoked"),
                              [self](beast::error_code) {});
      });
    });
  }

  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (ec) return finish();
    if (!ws_.got_text()) {
      buffer_.consume(buffer_.size());
      send_error("message: expected text (JSON), got binary");
      return read();
    }
    const std::string text = beast::buffers_to_string(buffer_.data());
    buffer_.consume(buffer_.size());
    last_activity_us_ = now_us();
    if (publisher_) {
      ++s_.frames_in;
      const Status st = s_.api.context().live.message(*publisher_, text);
      if (!st) send_error(st.error().message);
      if (publisher_->ended) {
        finish();
        ws_.async_close(websocket::close_code::normal, [self = shared_from_this()](beast::error_code) {});
        return;
      }
      if (s_.api.context().live.touch_due(*publisher_)) {
        net::post(s_.api_pool, [self = shared_from_this(), p = *publisher_] {
          try {
            self->s_.api.context().live.touch(p);
          } catch (const std::exception&) {
            // The database is away: the rig shows as stale until the next touch succeeds.
          }
        });
      }
      return read();
    }
    Result<std::vector<std::string>> wanted = parse_watch_message(text);
    if (!wanted) {
      send_error(wanted.error().message);
      return read();
    }
    // Trainees' requests need the store (is this rig theirs?): off the I/O thread.
    net::post(s_.api_pool, [self = shared_from_this(), rigs = std::move(wanted.value())] {
      Result<std::vector<std::string>> ok = make_error(503, "database unavailable, retry");
      try {
        ok = self->s_.api.context().live.allowed(self->caller_, rigs);
      } catch (const std::exception&) {
      }
      net::post(self->ws_.get_executor(), [self, ok = std::move(ok)]() mutable {
        if (!ok) {
          self->send_error(ok.error().message);
        } else {
          for (const std::string& rig : self->watching_) self->s_.hub.unsubscribe(rig, self.get());
          self->watching_ = std::move(ok.value());
          for (const std::string& rig : self->watching_) self->s_.hub.subscribe(rig, self, self->watch_restriction());
        }
        self->read();
      });
    });
  }

  void send_error(const std::string& line) {
    const nlohmann::json j = {{"type", "error"}, {"error", line}};
    enqueue(std::make_shared<const std::string>(safe_dump(j)));
  }

  void enqueue(const LiveMessage& message) {
    if (finished_) return;
    last_activity_us_ = now_us();
    if (queue_.size() >= s_.options.watcher_queue) {
      // Drop the oldest message not being written now.
      queue_.erase(queue_.begin() + (writing_ ? 1 : 0));
      ++s_.frames_dropped;
    }
    queue_.push_back(message);
    if (!writing_) write_next();
  }

  void write_next() {
    writing_ = true;
    ws_.text(true);
    ws_.async_write(net::buffer(*queue_.front()), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      self->queue_.pop_front();
      if (ec) {
        self->writing_ = false;
        return self->finish();
      }
      ++self->s_.frames_out;
      if (self->queue_.empty() || self->finished_) {
        self->writing_ = false;
      } else {
        self->write_next();
      }
    });
  }

  void finish() {
    if (finished_) return;
    finished_ = true;
    if (accepted_) --(publisher_ ? s_.publishers_now : s_.watchers_now);
    s_.hub.unsubscribe_all(this);
    if (publisher_) {
      net::post(s_.api_pool, [self = shared_from_this()] {
        try {
          self->s_.api.context().live.finish(*self->publisher_);
        } catch (const std::exception&) {
          // The database is away: the claim goes stale by itself.
        }
      });
    }
  }

  HttpServer::Impl& s_;
  ConnectionSlot slot_{s_.open_connections};
  std::unique_ptr<AddressSlot> address_slot_;
  std::unique_ptr<AccountSlot> account_slot_;
  websocket::stream<TlsOrPlainStream> ws_;
  std::int64_t last_activity_us_ = 0;  // the server's clock: the last message in or out
  std::int64_t next_recheck_us_ = 0;
  std::int64_t swept_before_accept_us_ = -1;  // the last sweep's time while the handshake was answered (-1: none)
  bool rechecking_ = false;
  beast::flat_buffer buffer_;
  Caller caller_;
  std::optional<Publisher> publisher_;
  std::vector<std::string> watching_;
  std::string first_message_;
  std::deque<LiveMessage> queue_;
  bool writing_ = false;
  bool finished_ = false;
  bool accepted_ = false;
};

}  // namespace

void start_ws_session(HttpServer::Impl& s, std::unique_ptr<AddressSlot> address_slot, std::unique_ptr<AccountSlot> account_slot,
                      TlsOrPlainStream&& stream, Caller caller, std::optional<Publisher> publisher, std::vector<std::string> watching,
                      std::string first_message, http::request<http::string_body> req) {
  auto ws = std::make_shared<WsSession>(s, std::move(address_slot), std::move(account_slot), std::move(stream), std::move(caller),
                                        std::move(publisher), std::move(watching), std::move(first_message));
  ws->start(std::move(req));
}

}  // namespace cathbox::server
