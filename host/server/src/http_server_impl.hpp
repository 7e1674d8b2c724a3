#pragma once
// The server's shared state (HttpServer::Impl): what its HTTP and WebSocket sessions count,
// reach and are swept by. Private to the server's sources.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "server/http_server.hpp"
#include "server/server_metrics.hpp"

namespace cathbox::server {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;

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
  net::ip::tcp::acceptor acceptor;
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
  void open_session(net::ip::tcp::socket socket);
};

}  // namespace cathbox::server
