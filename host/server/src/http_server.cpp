#include "server/http_server.hpp"

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
#include "http_session.hpp"
#include "http_fields.hpp"
#include "http_server_impl.hpp"
#include "live_opening.hpp"
#include "server/server_metrics.hpp"
#include "tls_or_plain_stream.hpp"
#include "tls_server_context.hpp"
#include "server/json_input.hpp"
#include "server/live_schema.hpp"

namespace cathbox::server {

using tcp = net::ip::tcp;

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
// The client address's share of the connections is taken first, before a byte is read or a
// handshake started: an address holding its share already is closed at once.
void HttpServer::Impl::open_session(tcp::socket socket) {
  beast::error_code ec;
  const tcp::endpoint peer = socket.remote_endpoint(ec);
  auto address = std::make_unique<AddressSlot>(*this, ec ? std::string("unknown") : peer.address().to_string());
  if (!address->taken()) {
    socket.close(ec);
    return;
  }
  std::shared_ptr<net::ssl::context> context = current_tls();
  beast::tcp_stream connection(std::move(socket));
  if (!context) {
    return start_http_session(*this, std::move(address), TlsOrPlainStream(std::move(connection)), beast::flat_buffer());
  }
  connection.expires_after(std::chrono::seconds(options.idle_timeout_s));
  auto stream = std::make_shared<TlsOrPlainStream>(std::move(connection), context);
  auto buffer = std::make_shared<beast::flat_buffer>();
  auto slot = std::make_shared<ConnectionSlot>(open_connections);
  auto held = std::make_shared<std::unique_ptr<AddressSlot>>(std::move(address));
  beast::async_detect_ssl(stream->next_layer(), *buffer, [this, stream, buffer, slot, held](beast::error_code dec, bool tls) {
    if (dec) return;
    if (!tls) {
      return start_http_session(*this, std::move(*held), TlsOrPlainStream(std::move(stream->next_layer())), std::move(*buffer), true);
    }
    stream->tls().async_handshake(net::ssl::stream_base::server, buffer->data(),
                                  [this, stream, buffer, slot, held](beast::error_code hec, std::size_t used) {
                                    if (hec) return;  // not a TLS client, or no common version: nothing to say
                                    buffer->consume(used);
                                    start_http_session(*this, std::move(*held), std::move(*stream), std::move(*buffer));
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
