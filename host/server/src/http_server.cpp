#include "server/http_server.hpp"

#include <atomic>
#include <charconv>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>
#include <unordered_map>

#include <boost/asio/dispatch.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/core/detect_ssl.hpp>

#include "api_call.hpp"
#include "server/server_metrics.hpp"
#include "tls_or_plain_stream.hpp"
#include "tls_server_context.hpp"
#include "server/json_input.hpp"
#include "server/live_schema.hpp"

namespace cathbox::server {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

// An open WebSocket, as the sweep sees it (http_server.hpp: idle eviction, token rechecks).
class SweptSocket {
 public:
  virtual ~SweptSocket() = default;
  virtual void sweep(std::int64_t now_us) = 0;
};

struct HttpServer::Impl {
  Api& api;
  LiveHub& hub;
  HttpServerOptions options;
  net::io_context ioc;
  tcp::acceptor acceptor;
  net::thread_pool api_pool;
  net::thread_pool heavy_pool;
  std::vector<std::thread> threads;
  std::atomic<int> heavy_queued{0};
  std::atomic<std::size_t> open_connections{0};
  std::mutex per_address_mutex;
  std::unordered_map<std::string, std::size_t> per_address;  // open connections by client address
  bool started = false;
  bool stopped = false;
  std::mutex stop_mutex;
  std::mutex tls_mutex;
  std::shared_ptr<net::ssl::context> tls_context;  // null: plain HTTP

  std::shared_ptr<net::ssl::context> current_tls() {
    std::lock_guard lock(tls_mutex);
    return tls_context;
  }

  std::atomic<std::uint64_t> connections{0}, requests{0}, publishers{0}, watchers{0}, frames_in{0}, frames_out{0}, frames_dropped{0};
  // The open WebSockets (swept on the server's clock) and how many each account holds.
  std::mutex ws_mutex;
  std::vector<std::weak_ptr<SweptSocket>> ws_sockets;
  std::unordered_map<std::int64_t, std::size_t> ws_per_account;
  std::unique_ptr<net::steady_timer> sweeper;
  std::atomic<std::uint64_t> publishers_now{0}, watchers_now{0};
  ServerMetrics metrics;

  ScrapeGauges gauges() {
    return ScrapeGauges{open_connections.load(), publishers_now.load(), watchers_now.load(), heavy_queued.load(),
                        api.context().store.database().pool_stats(), frames_in.load(), frames_out.load(), frames_dropped.load()};
  }

  Impl(Api& a, LiveHub& h, HttpServerOptions o)
      : api(a),
        hub(h),
        options(std::move(o)),
        ioc(std::max(1, options.io_threads)),
        acceptor(net::make_strand(ioc)),
        api_pool(static_cast<std::size_t>(std::max(1, options.api_threads))),
        heavy_pool(static_cast<std::size_t>(std::max(1, options.heavy_threads))) {}

  void accept();
  void sweep();
  void schedule_sweep();
  void open_session(tcp::socket socket);
};

namespace {

std::string_view sv(beast::string_view s) { return {s.data(), s.size()}; }

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

// Every answer, API or page: the pages run only their own scripts and modules (no inline
// script, no eval, no other origin; WebAssembly compiled from their own files), are never
// framed, and no type is sniffed. Cross-origin isolated (COOP + COEP): the trainee page's
// WebAssembly session shares memory with its threads (SharedArrayBuffer).
void security_headers(http::response<http::string_body>& res) {
  res.set("Content-Security-Policy",
          "default-src 'self'; script-src 'self' 'wasm-unsafe-eval'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; "
          "connect-src 'self'; object-src 'none'; base-uri 'none'; form-action 'self'; frame-ancestors 'none'");
  res.set("X-Frame-Options", "DENY");
  res.set("X-Content-Type-Options", "nosniff");
  res.set("Referrer-Policy", "no-referrer");
  res.set("Cross-Origin-Opener-Policy", "same-origin");
  res.set("Cross-Origin-Embedder-Policy", "require-corp");
}

// "bearer.TOKEN" out of a Sec-WebSocket-Protocol list ("cathbox, bearer.TOKEN"); empty if none.
std::string bearer_from_subprotocols(std::string_view list) {
  while (!list.empty()) {
    const std::size_t comma = std::min(list.find(','), list.size());
    std::string_view item = list.substr(0, comma);
    list.remove_prefix(std::min(comma + 1, list.size()));
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
    if (item.rfind("bearer.", 0) == 0 && item.size() > 7) return std::string(item.substr(7));
  }
  return {};
}

std::string content_type_for(const std::filesystem::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  if (ext == ".ico") return "image/x-icon";
  if (ext == ".wasm") return "application/wasm";
  if (ext == ".txt" || ext == ".md") return "text/plain; charset=utf-8";
  return "application/octet-stream";
}

ApiRequest to_api_request(const http::request<http::string_body>& req, const std::string& remote) {
  ApiRequest r;
  r.method = std::string(req.method_string());
  r.target = std::string(req.target());
  r.authorization = std::string(req[http::field::authorization]);
  r.content_type = std::string(req[http::field::content_type]);
  r.accept_encoding = std::string(req[http::field::accept_encoding]);
  r.if_none_match = std::string(req[http::field::if_none_match]);
  r.body = req.body();
  r.remote_address = remote;
  return r;
}

// An error answer for a failed authentication; a 401 names the scheme (RFC 9110 section 11.6.1).
ApiResponse auth_refusal(const Error& e) {
  ApiResponse r = error_response(e);
  if (e.status == 401) r.headers.emplace_back("WWW-Authenticate", "Bearer");
  return r;
}

// ---- WebSocket ------------------------------------------------------------------------------

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
    auto self = shared_from_this();
    ws_.async_accept(req, [self](beast::error_code ec) { self->on_accept(ec); });
  }

  void deliver(const LiveMessage& message) override {
    net::post(ws_.get_executor(), [self = shared_from_this(), message] { self->enqueue(message); });
  }

  // On the server's clock (http_server.hpp): an idle socket closes; the token is checked again
  // every ws_recheck_s.
  void sweep(std::int64_t now_us) override {
    net::post(ws_.get_executor(), [self = shared_from_this(), now_us] {
      if (self->finished_) return;
      const std::int64_t idle_us = std::int64_t{self->s_.options.ws_idle_timeout_s} * 1'000'000;
      if (self->evictable_when_idle() && now_us - self->last_activity_us_ >= idle_us) {
        self->finish();
        self->ws_.async_close(websocket::close_reason(websocket::close_code::going_away, "idle"), [self](beast::error_code) {});
        return;
      }
      if (!self->rechecking_ && now_us >= self->next_recheck_us_) self->recheck();
    });
  }

 private:
  void on_accept(beast::error_code ec) {
    if (ec) return finish();
    accepted_ = true;
    last_activity_us_ = now_us();
    next_recheck_us_ = last_activity_us_ + recheck_us();
    {
      std::lock_guard lock(s_.ws_mutex);
      std::erase_if(s_.ws_sockets, [](const std::weak_ptr<SweptSocket>& w) { return w.expired(); });
      s_.ws_sockets.push_back(shared_from_this());
    }
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

// ---- HTTP -----------------------------------------------------------------------------------

class HttpSession final : public std::enable_shared_from_this<HttpSession> {
 public:
  // `buffer`: bytes already read (the TLS detection's); `plain_on_tls_port`: answer 400 and close.
  HttpSession(HttpServer::Impl& s, TlsOrPlainStream&& stream, beast::flat_buffer&& buffer, bool plain_on_tls_port = false)
      : s_(s), stream_(std::move(stream)), buffer_(std::move(buffer)), plain_on_tls_port_(plain_on_tls_port) {
    beast::error_code ec;
    const tcp::endpoint peer = stream_.next_layer().socket().remote_endpoint(ec);
    remote_ = ec ? "unknown" : peer.address().to_string();
    address_slot_ = std::make_unique<AddressSlot>(s_, remote_);
  }

  void run() {
    if (!address_slot_->taken()) {
      // This address holds its share of the connections already: closed before a byte is read.
      beast::error_code ignored;
      stream_.next_layer().socket().close(ignored);
      return;
    }
    net::dispatch(stream_.get_executor(), [self = shared_from_this()] { self->read_header(); });
  }

 private:
  void read_header() {
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(s_.options.max_header_bytes));
    // The route's own limit is set once the header is in (a larger one here only lets the
    // header through; no body byte is read before on_header checks it).
    parser_->body_limit(std::max({kMaxJsonBodyBytes, kMaxCaseUploadBytes, kMaxRecordBytes}));
    stream_.expires_after(std::chrono::seconds(s_.options.idle_timeout_s));
    http::async_read_header(stream_, buffer_, *parser_,
                            [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_header(ec); });
  }

  static bool quiet_end(const beast::error_code& ec) {
    return ec == http::error::end_of_stream || ec == net::error::eof || ec == beast::error::timeout ||
           ec == net::error::connection_reset || ec == net::error::operation_aborted || ec == net::error::broken_pipe;
  }

  void on_header(beast::error_code ec) {
    if (quiet_end(ec) && buffer_.size() == 0) return close();
    if (ec == http::error::body_limit) {
      // A Content-Length over every route's limit: refused from the header alone.
      return answer_error(413, "body: Content-Length is over the largest limit of any endpoint (" +
                                   std::to_string(std::max({kMaxJsonBodyBytes, kMaxCaseUploadBytes, kMaxRecordBytes})) + " bytes)",
                          false, 11);
    }
    if (ec) return answer_error(ec == http::error::header_limit ? 431 : 400, "request: " + ec.message(), false, 11);
    const auto& req = parser_->get();
    route_ = ServerMetrics::route_of(sv(req.method_string()), sv(req.target()));
    if (plain_on_tls_port_) {
      return answer_error(400, "this port speaks HTTPS: use https://", false, req.version());
    }
    const std::size_t limit = Api::body_limit(sv(req.method_string()), sv(req.target()));
    const auto length = parser_->content_length();
    if (length && *length > limit) {
      return answer_error(413, "body: " + std::to_string(*length) + " bytes is over the limit of " + std::to_string(limit) + " for " +
                                   std::string(req.method_string()) + " " + std::string(req.target().substr(0, req.target().find('?'))),
                          false, req.version());
    }
    parser_->body_limit(limit);
    if (parser_->is_done()) return on_request();
    // An upload (a body allowed over the JSON limit) or a client waiting for 100 Continue: the
    // token is checked before a byte of the body is read or asked for. Other bodies are at most
    // kMaxJsonBodyBytes, read under the idle deadline.
    const bool expects_continue = beast::iequals(req[http::field::expect], "100-continue");
    const std::string_view target = sv(req.target());
    const bool api = target.rfind("/api/", 0) == 0;
    if (api && (limit > kMaxJsonBodyBytes || expects_continue) && !Api::is_login(sv(req.method_string()), target)) {
      net::post(s_.api_pool, [self = shared_from_this(), authorization = std::string(req[http::field::authorization])] {
        ApiResponse refusal;
        bool ok = false;
        try {
          Result<Caller> who = self->s_.api.context().auth.authenticate(authorization);
          if (who) {
            ok = true;
          } else {
            refusal = error_response(who.error());
            refusal.headers.emplace_back("WWW-Authenticate", "Bearer");
          }
        } catch (const std::exception&) {
          refusal = error_response(make_error(503, "database unavailable, retry"));
        }
        net::post(self->stream_.get_executor(), [self, ok, refusal = std::move(refusal)]() mutable {
          if (!ok) return self->answer(std::move(refusal), false, self->parser_->get().version());
          self->read_body_after_header();
        });
      });
      return;
    }
    read_body_after_header();
  }

  void read_body_after_header() {
    const auto& req = parser_->get();
    stream_.expires_after(std::chrono::seconds(s_.options.body_timeout_s));
    if (beast::iequals(req[http::field::expect], "100-continue")) {
      auto cont = std::make_shared<http::response<http::empty_body>>(http::status::continue_, req.version());
      return http::async_write(stream_, *cont, [self = shared_from_this(), cont](beast::error_code wec, std::size_t) {
        if (wec) return self->close();
        self->read_body();
      });
    }
    read_body();
  }

  void read_body() {
    http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec == http::error::body_limit) {
        return self->answer_error(413, "body: over the limit of this endpoint", false, self->parser_->get().version());
      }
      if (quiet_end(ec)) return self->close();
      if (ec) return self->answer_error(400, "request: " + ec.message(), false, 11);
      self->on_request();
    });
  }

  void on_request() {
    ++s_.requests;
    request_read_ = std::chrono::steady_clock::now();
    http::request<http::string_body> req = parser_->release();
    const std::string_view target(req.target().data(), req.target().size());
    if (websocket::is_upgrade(req)) return upgrade(std::move(req));
    if (target.rfind("/api/", 0) == 0 || target == "/api") return call_api(std::move(req));
    const std::string_view path = target.substr(0, target.find('?'));
    if (path == "/healthz" || path == "/readyz" || path == "/metrics") return serve_operations(req, path);
    serve_static(req);
  }

  // /healthz: the process answers. /readyz: and its database does. /metrics: Prometheus text,
  // for loopback callers or an admin's token.
  void serve_operations(const http::request<http::string_body>& req, std::string_view path) {
    const bool keep_alive = req.keep_alive();
    const unsigned version = req.version();
    if (req.method() != http::verb::get && req.method() != http::verb::head) {
      return answer_error(405, std::string(req.method_string()) + " is not allowed on " + std::string(path), keep_alive, version);
    }
    const auto text = [](int status, std::string body) {
      ApiResponse r;
      r.status = status;
      r.content_type = "text/plain; charset=utf-8";
      r.body = std::move(body);
      return r;
    };
    if (path == "/healthz") return answer(text(200, "ok\n"), keep_alive, version);
    const bool metrics = path == "/metrics";
    beast::error_code ec;
    const net::ip::address peer = net::ip::make_address(remote_, ec);
    const bool local = !ec && (peer.is_loopback() || (peer.is_v6() && peer.to_v6().is_v4_mapped() &&
                                                      net::ip::make_address_v4(net::ip::v4_mapped, peer.to_v6()).is_loopback()));
    net::post(s_.api_pool, [self = shared_from_this(), metrics, local, token = std::string(req[http::field::authorization]), keep_alive,
                            version, text]() mutable {
      ApiResponse r;
      try {
        if (!metrics) {
          self->s_.api.context().store.database().transact(TxMode::kRead, [](SqlSession& s) { (void)s.query("SELECT 1"); });
          r = text(200, "ready\n");
        } else {
          Result<Caller> who = local ? Result<Caller>(Caller{}) : self->s_.api.context().auth.authenticate(token);
          if (!who) {
            r = auth_refusal(who.error());
          } else if (!local && who.value().role != Role::kAdmin) {
            r = error_response(make_error(403, "/metrics: for loopback callers and admins"));
          } else {
            r = text(200, self->s_.metrics.render(self->s_.gauges()));
            r.content_type = "text/plain; version=0.0.4; charset=utf-8";
          }
        }
      } catch (const std::exception& e) {
        r = metrics ? error_response(make_error(503, std::string("database unavailable, retry: ") + e.what()))
                    : text(503, std::string("not ready: database unavailable: ") + e.what() + "\n");
      }
      net::post(self->stream_.get_executor(),
                [self, r = std::move(r), keep_alive, version]() mutable { self->answer(std::move(r), keep_alive, version); });
    });
  }

  void call_api(http::request<http::string_body> req) {
    const bool heavy = Api::is_heavy(sv(req.method_string()), sv(req.target()));
    const bool keep_alive = req.keep_alive();
    const unsigned version = req.version();
    if (heavy && s_.heavy_queued.load() >= s_.options.max_heavy_queued) {
      return answer(error_response(make_error(503, "server busy checking uploads; retry")), keep_alive, version);
    }
    ApiRequest ar = to_api_request(req, remote_);
    if (heavy) ++s_.heavy_queued;
    net::post(heavy ? s_.heavy_pool : s_.api_pool, [self = shared_from_this(), ar = std::move(ar), heavy, keep_alive, version]() mutable {
      const auto began = std::chrono::steady_clock::now();
      ApiResponse r = self->s_.api.handle(ar);
      if (heavy) {
        self->s_.metrics.observe_upload_check(std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count());
        --self->s_.heavy_queued;
      }
      net::post(self->stream_.get_executor(),
                [self, r = std::move(r), keep_alive, version]() mutable { self->answer(std::move(r), keep_alive, version); });
    });
  }

  void answer_error(int status, const std::string& line, bool keep_alive, unsigned version) {
    answer(error_response(make_error(status, line)), keep_alive, version);
  }

  void answer(ApiResponse r, bool keep_alive, unsigned version) {
    auto res = std::make_shared<http::response<http::string_body>>();
    res->version(version == 10 ? 10 : 11);
    res->result(static_cast<unsigned>(r.status));
    res->set(http::field::server, "cathbox-server");
    security_headers(*res);
    if (!r.content_type.empty()) res->set(http::field::content_type, r.content_type);
    if (stream_.is_tls()) res->set(http::field::strict_transport_security, "max-age=31536000");
    for (const auto& [name, value] : r.headers) res->set(name, value);
    // API answers are not cached unless they say so (case bundles: revalidated by their ETag).
    if (res->find(http::field::cache_control) == res->end()) res->set(http::field::cache_control, "no-store");
    res->body() = std::move(r.body);
    res->keep_alive(keep_alive);
    res->prepare_payload();
    // A fresh deadline for the write: the one set when the request was read may have passed while
    // a heavy handler (a replay of a long record) ran, which cut the answer short.
    stream_.expires_after(std::chrono::seconds(s_.options.body_timeout_s));
    http::async_write(stream_, *res, [self = shared_from_this(), res, keep_alive](beast::error_code ec, std::size_t) {
      self->s_.metrics.observe_request(self->route_, static_cast<int>(res->result_int()),
                                       std::chrono::duration<double>(std::chrono::steady_clock::now() - self->request_read_).count());
      if (ec || !keep_alive) return self->close();
      self->read_header();
    });
  }

  void serve_static(const http::request<http::string_body>& req) {
    const bool keep_alive = req.keep_alive();
    if (req.method() != http::verb::get && req.method() != http::verb::head) {
      return answer_error(405, std::string(req.method_string()) + " is not allowed on static files", keep_alive, req.version());
    }
    Result<api::Target> target = api::parse_target(std::string_view(req.target().data(), req.target().size()));
    if (!target) return answer(error_response(target.error()), keep_alive, req.version());
    const std::string& path = target.value().path;
    const StaticMount* mount = nullptr;
    for (const StaticMount& m : s_.options.mounts) {
      if (path.rfind(m.url_prefix, 0) == 0 && (mount == nullptr || m.url_prefix.size() > mount->url_prefix.size())) mount = &m;
    }
    const std::string missing = "no file " + path.substr(0, 200);
    if (mount == nullptr) return answer_error(404, missing, keep_alive, req.version());
    // The segments after the mount's prefix, each a plain name.
    std::filesystem::path file(mount->folder);
    const std::size_t skip = static_cast<std::size_t>(std::count(mount->url_prefix.begin(), mount->url_prefix.end(), '/')) - 1;
    for (std::size_t i = skip; i < target.value().segments.size(); ++i) {
      const std::string& seg = target.value().segments[i];
      if (seg.empty() || seg[0] == '.' || seg.find('/') != std::string::npos || seg.find('\\') != std::string::npos) {
        return answer_error(404, missing, keep_alive, req.version());
      }
      file /= seg;
    }
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec)) file /= "index.html";
    if (!std::filesystem::is_regular_file(file, ec)) return answer_error(404, missing, keep_alive, req.version());
    const auto size = std::filesystem::file_size(file, ec);
    if (ec || size > 64 * 1024 * 1024) return answer_error(404, missing, keep_alive, req.version());
    std::ifstream in(file, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    ApiResponse r;
    r.content_type = content_type_for(file);
    r.body = req.method() == http::verb::head ? std::string() : bytes.str();
    r.headers.emplace_back("Cache-Control", "no-cache");
    answer(std::move(r), keep_alive, req.version());
  }

  void upgrade(http::request<http::string_body> req) {
    const bool keep_alive = false;
    Result<api::Target> parsed = api::parse_target(std::string_view(req.target().data(), req.target().size()));
    if (!parsed) return answer(error_response(parsed.error()), keep_alive, req.version());
    const api::Target& t = parsed.value();
    const auto& seg = t.segments;
    const bool publisher = seg.size() == 6 && seg[0] == "api" && seg[1] == "v1" && seg[2] == "live" && seg[3] == "rigs" && seg[5] == "stream";
    const bool watcher = seg.size() == 4 && seg[0] == "api" && seg[1] == "v1" && seg[2] == "live" && seg[3] == "watch";
    if (!publisher && !watcher) return answer_error(404, "no WebSocket endpoint " + t.path, keep_alive, req.version());
    // The token travels in a header, never in the URL (where proxies and logs keep it).
    std::string token(req[http::field::authorization]);
    if (token.empty()) token = bearer_from_subprotocols(sv(req[http::field::sec_websocket_protocol]));
    // Everything that needs the store happens on the API threads, before the upgrade.
    net::post(s_.api_pool, [self = shared_from_this(), req = std::move(req), t, token, publisher]() mutable {
      ApiResponse refusal;
      std::optional<Caller> caller;
      std::optional<Publisher> pub;
      std::vector<std::string> rigs;
      std::string first;
      try {
        Result<Caller> who = self->s_.api.context().auth.authenticate(token);
        if (!who) {
          refusal = auth_refusal(who.error());
        } else if (publisher) {
          const auto q = [&](const char* k) { const auto it = t.query.find(k); return it == t.query.end() ? std::string() : it->second; };
          const std::string version = q("version");
          const std::string assignment = q("assignment");
          std::int64_t v = 0, a = 0;
          const bool v_ok = version.empty() || (std::from_chars(version.data(), version.data() + version.size(), v).ec == std::errc() && v >= 0 && v < 1'000'000);
          const bool a_ok = assignment.empty() || (std::from_chars(assignment.data(), assignment.data() + assignment.size(), a).ec == std::errc() && a > 0);
          if (!v_ok || !a_ok) {
            refusal = error_response(make_error(400, !v_ok ? "query 'version': expected a number" : "query 'assignment': expected an id"));
          } else {
            Result<Publisher> started = self->s_.api.context().live.start(
                who.value(), t.segments[4], q("case"), static_cast<int>(v), assignment.empty() ? std::nullopt : std::optional<std::int64_t>(a));
            if (!started) {
              refusal = error_response(started.error());
            } else {
              pub = std::move(started.value());
              caller = who.value();
            }
          }
        } else {
          const auto it = t.query.find("rigs");
          std::string list = it == t.query.end() ? std::string() : it->second;
          nlohmann::json wanted = nlohmann::json::array();
          for (std::size_t at = 0; at < list.size();) {
            const std::size_t comma = std::min(list.find(',', at), list.size());
            if (comma > at) wanted.push_back(list.substr(at, comma - at));
            at = comma + 1;
          }
          Result<std::vector<std::string>> parsed_rigs = parse_watch_message(safe_dump(nlohmann::json{{"type", "watch"}, {"rigs", wanted}}));
          Result<std::vector<std::string>> ok =
              parsed_rigs ? self->s_.api.context().live.allowed(who.value(), parsed_rigs.value()) : parsed_rigs;
          if (!ok) {
            refusal = error_response(ok.error());
          } else {
            rigs = std::move(ok.value());
            caller = who.value();
            first = self->s_.api.context().live.rigs_message(who.value()).dump();
          }
        }
      } catch (const StoreError& e) {
        refusal = error_response(make_error(503, std::string("database unavailable, retry: ") + e.what()));
      } catch (const std::exception& e) {
        refusal = error_response(make_error(500, std::string("internal error: ") + e.what()));
      }
      net::post(self->stream_.get_executor(), [self, req = std::move(req), refusal = std::move(refusal), caller = std::move(caller),
                                               pub = std::move(pub), rigs = std::move(rigs), first = std::move(first)]() mutable {
        if (!caller) return self->answer(std::move(refusal), false, req.version());
        self->open_websocket(std::move(req), std::move(*caller), std::move(pub), std::move(rigs), std::move(first));
      });
    });
  }

  // The upgrade, within the account's share of WebSockets (else 429, and a stream just started
  // is ended again).
  void open_websocket(http::request<http::string_body> req, Caller caller, std::optional<Publisher> pub, std::vector<std::string> rigs,
                      std::string first) {
    auto account = std::make_unique<AccountSlot>(s_, caller.user_id);
    if (!account->taken()) {
      if (pub) {
        net::post(s_.api_pool, [self = shared_from_this(), p = std::move(*pub)]() mutable {
          try {
            self->s_.api.context().live.finish(p);
          } catch (const std::exception&) {
            // The database is away: the claim goes stale by itself.
          }
        });
      }
      return answer_error(429, "live: this account holds " + std::to_string(s_.options.max_websockets_per_account) +
                                   " live connections already (the limit)", false, req.version());
    }
    auto ws = std::make_shared<WsSession>(s_, std::move(address_slot_), std::move(account), std::move(stream_), std::move(caller),
                                          std::move(pub), std::move(rigs), std::move(first));
    ws->start(std::move(req));
  }

  void close() {
    if (stream_.is_tls()) {
      // close_notify, then the TCP half-close (a peer that never answers is cut by the deadline).
      stream_.expires_after(std::chrono::seconds(5));
      return stream_.tls().async_shutdown([self = shared_from_this()](beast::error_code) {
        beast::error_code ec;
        self->stream_.next_layer().socket().shutdown(tcp::socket::shutdown_send, ec);
      });
    }
    beast::error_code ec;
    stream_.next_layer().socket().shutdown(tcp::socket::shutdown_send, ec);
  }

  HttpServer::Impl& s_;
  ConnectionSlot slot_{s_.open_connections};
  std::unique_ptr<AddressSlot> address_slot_;
  TlsOrPlainStream stream_;
  beast::flat_buffer buffer_;
  bool plain_on_tls_port_ = false;
  std::string route_ = "unparsed";
  std::chrono::steady_clock::time_point request_read_ = std::chrono::steady_clock::now();
  std::optional<http::request_parser<http::string_body>> parser_;
  std::string remote_;
};

}  // namespace

void HttpServer::Impl::accept() {
  acceptor.async_accept(net::make_strand(ioc), [this](beast::error_code ec, tcp::socket socket) {
    if (ec == net::error::operation_aborted || !acceptor.is_open()) return;
    if (!ec) {
      ++connections;
      if (open_connections.load() >= options.max_connections) {
        beast::error_code ignored;
        socket.close(ignored);
      } else {
        open_session(std::move(socket));
      }
    }
    accept();
  });
}

void HttpServer::Impl::sweep() {
  const std::int64_t now = api.context().clock.now_us();
  std::vector<std::shared_ptr<SweptSocket>> open;
  {
    std::lock_guard lock(ws_mutex);
    std::erase_if(ws_sockets, [](const std::weak_ptr<SweptSocket>& w) { return w.expired(); });
    for (const std::weak_ptr<SweptSocket>& w : ws_sockets) {
      if (auto p = w.lock()) open.push_back(std::move(p));
    }
  }
  for (const std::shared_ptr<SweptSocket>& socket : open) socket->sweep(now);
  // The store claims of this instance's open streams, silent or not (off the I/O threads).
  net::post(api_pool, [this] {
    try {
      api.context().live.keep_claims();
    } catch (const std::exception&) {
      // The database is away: the claims are refreshed on a later sweep.
    }
  });
}

void HttpServer::Impl::schedule_sweep() {
  sweeper->expires_after(std::chrono::milliseconds(options.sweep_every_ms));
  sweeper->async_wait([this](beast::error_code ec) {
    if (ec) return;
    sweep();
    schedule_sweep();
  });
}

void HttpServer::sweep() { impl_->sweep(); }

// Plain HTTP, or on a TLS port: a look at the first bytes, then the handshake (a client speaking
// plain HTTP there is answered 400 in plain HTTP, saying so).
void HttpServer::Impl::open_session(tcp::socket socket) {
  std::shared_ptr<net::ssl::context> context = current_tls();
  beast::tcp_stream connection(std::move(socket));
  if (!context) return std::make_shared<HttpSession>(*this, TlsOrPlainStream(std::move(connection)), beast::flat_buffer())->run();
  connection.expires_after(std::chrono::seconds(options.idle_timeout_s));
  auto stream = std::make_shared<TlsOrPlainStream>(std::move(connection), context);
  auto buffer = std::make_shared<beast::flat_buffer>();
  auto slot = std::make_shared<ConnectionSlot>(open_connections);
  beast::async_detect_ssl(stream->next_layer(), *buffer, [this, stream, buffer, slot](beast::error_code ec, bool tls) {
    if (ec) return;
    if (!tls) {
      return std::make_shared<HttpSession>(*this, TlsOrPlainStream(std::move(stream->next_layer())), std::move(*buffer), true)->run();
    }
    stream->tls().async_handshake(net::ssl::stream_base::server, buffer->data(),
                                  [this, stream, buffer, slot](beast::error_code hec, std::size_t used) {
                                    if (hec) return;  // not a TLS client, or no common version: nothing to say
                                    buffer->consume(used);
                                    std::make_shared<HttpSession>(*this, std::move(*stream), std::move(*buffer))->run();
                                  });
  });
}

HttpServer::HttpServer(Api& api, LiveHub& hub, HttpServerOptions options)
    : impl_(std::make_unique<Impl>(api, hub, std::move(options))) {}

HttpServer::~HttpServer() { stop(); }

Result<std::uint16_t> HttpServer::start() {
  Impl& s = *impl_;
  beast::error_code ec;
  const net::ip::address address = net::ip::make_address(s.options.host, ec);
  if (ec) return make_error(400, "--listen: '" + s.options.host + "' is not an IP address");
  if (s.options.tls) {
    Result<std::shared_ptr<net::ssl::context>> context = make_server_tls_context(*s.options.tls);
    if (!context) return context.error();
    s.tls_context = context.value();
  } else if (!address.is_loopback() && !s.options.insecure_http) {
    return make_error(400, "--listen " + s.options.host +
                               ": not a loopback address, and no --tls-cert/--tls-key: passwords and tokens would cross the "
                               "network in clear (give --insecure-http only behind a TLS proxy)");
  }
  const tcp::endpoint endpoint(address, s.options.port);
  s.acceptor.open(endpoint.protocol(), ec);
  if (!ec) s.acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) s.acceptor.bind(endpoint, ec);
  if (!ec) s.acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec) return make_error(503, "--listen " + s.options.host + ":" + std::to_string(s.options.port) + ": " + ec.message());
  const std::uint16_t port = s.acceptor.local_endpoint().port();
  s.accept();
  if (s.options.sweep_every_ms > 0) {
    s.sweeper = std::make_unique<net::steady_timer>(s.ioc);
    s.schedule_sweep();
  }
  s.started = true;
  for (int i = 0; i < std::max(1, s.options.io_threads); ++i) s.threads.emplace_back([&s] { s.ioc.run(); });
  return port;
}

void HttpServer::stop() {
  Impl& s = *impl_;
  std::lock_guard lock(s.stop_mutex);
  if (s.stopped) return;
  s.stopped = true;
  net::post(s.acceptor.get_executor(), [&s] {
    beast::error_code ec;
    s.acceptor.close(ec);
  });
  s.ioc.stop();
  for (std::thread& t : s.threads) t.join();
  s.threads.clear();
  s.heavy_pool.stop();
  s.api_pool.stop();
  s.heavy_pool.join();
  s.api_pool.join();
}

Status HttpServer::reload_tls() {
  Impl& s = *impl_;
  if (!s.options.tls) return make_error(400, "TLS reload: this server speaks plain HTTP (no --tls-cert)");
  Result<std::shared_ptr<net::ssl::context>> context = make_server_tls_context(*s.options.tls);
  if (!context) return context.error();
  std::lock_guard lock(s.tls_mutex);
  s.tls_context = context.value();
  return Ok{};
}

bool HttpServer::tls() const { return impl_->options.tls.has_value(); }

HttpServerStats HttpServer::stats() const {
  const Impl& s = *impl_;
  return HttpServerStats{s.connections.load(), s.requests.load(), s.publishers.load(), s.watchers.load(),
                         s.frames_in.load(),   s.frames_out.load(), s.frames_dropped.load()};
}

std::vector<StaticMount> default_mounts(const std::string& web_root) {
  return {{"/", web_root}, {"/lib/three/", "/usr/share/javascript/three"}, {"/lib/chart.js/", "/usr/share/javascript/chart.js"}};
}

}  // namespace cathbox::server
