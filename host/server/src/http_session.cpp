#include "http_session.hpp"

#include <atomic>
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
#include "connection_slots.hpp"
#include "http_fields.hpp"
#include "http_server_impl.hpp"
#include "live_opening.hpp"
#include "server/server_metrics.hpp"
#include "tls_or_plain_stream.hpp"
#include "tls_server_context.hpp"
#include "ws_session.hpp"
#include "server/json_input.hpp"
#include "server/live_schema.hpp"

namespace cathbox::server {

using tcp = net::ip::tcp;

namespace {

class HttpSession final : public std::enable_shared_from_this<HttpSession> {
 public:
  // `address_slot`: the client address's share, taken when the connection was accepted (before
  // any TLS handshake); `buffer`: bytes already read (the TLS detection's); `plain_on_tls_port`:
  // answer 400 and close.
  HttpSession(HttpServer::Impl& s, std::unique_ptr<AddressSlot> address_slot, TlsOrPlainStream&& stream,
              beast::flat_buffer&& buffer, bool plain_on_tls_port = false)
      : s_(s),
        address_slot_(std::move(address_slot)),
        stream_(std::move(stream)),
        buffer_(std::move(buffer)),
        plain_on_tls_port_(plain_on_tls_port),
        remote_(address_slot_->address()) {}

  void run() {
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
    const LiveEndpoint endpoint = live_endpoint(t);
    if (endpoint == LiveEndpoint::kNone) return answer_error(404, "no WebSocket endpoint " + t.path, keep_alive, req.version());
    // The token travels in a header, never in the URL (where proxies and logs keep it).
    std::string token(req[http::field::authorization]);
    if (token.empty()) token = bearer_from_subprotocols(sv(req[http::field::sec_websocket_protocol]));
    // Everything that needs the store happens on the API threads, before the upgrade.
    net::post(s_.api_pool, [self = shared_from_this(), req = std::move(req), t, token, endpoint]() mutable {
      LiveOpening o = open_live(self->s_.api.context(), t, token, endpoint);
      net::post(self->stream_.get_executor(), [self, req = std::move(req), o = std::move(o)]() mutable {
        if (!o.caller) return self->answer(std::move(o.refusal), false, req.version());
        self->open_websocket(std::move(req), std::move(*o.caller), std::move(o.publisher), std::move(o.rigs), std::move(o.first_message));
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
    start_ws_session(s_, std::move(address_slot_), std::move(account), std::move(stream_), std::move(caller), std::move(pub), std::move(rigs),
                     std::move(first), std::move(req));
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

void start_http_session(HttpServer::Impl& s, std::unique_ptr<AddressSlot> address_slot, TlsOrPlainStream&& stream,
                        beast::flat_buffer&& buffer, bool plain_on_tls_port) {
  std::make_shared<HttpSession>(s, std::move(address_slot), std::move(stream), std::move(buffer), plain_on_tls_port)->run();
}

}  // namespace cathbox::server
