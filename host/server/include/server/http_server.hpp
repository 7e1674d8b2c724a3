#pragma once
// HTTP/1.1 and WebSocket for the API (Boost.Beast; the header keeps Beast out of its users).
//
// Threads: io_threads run the sockets; API handlers (which wait on the database and Argon2)
// run on api_threads; case and record uploads (meshing, replaying) on heavy_threads with at most
// max_heavy_queued waiting, beyond which the answer is 503 + Retry-After.
//
// TLS (options.tls, server/tls.hpp): every answer carries Strict-Transport-Security; the live
// sockets are wss://. A plain-HTTP request on the TLS port is answered 400 "this port speaks
// HTTPS". Without TLS, start() refuses a non-loopback address unless options.insecure_http.
//
// Limits: a header over max_header_bytes is 431; a body over the route's limit
// (Api::body_limit) is 413 before it is read; an upload's token (and any request sending
// `Expect: 100-continue`) is checked before its body is read or 100 Continue is sent; an idle
// connection closes after idle_timeout_s; a WebSocket message over the live schema's limit
// closes that socket; one address holds at most max_connections_per_address connections.
// Every answer carries Content-Security-Policy (own scripts only), X-Frame-Options: DENY and
// X-Content-Type-Options: nosniff.
//
// Static files: every path outside /api/ is looked up in the mounts (longest prefix wins),
// without a token: "/" is host/server/web/, "/lib/three/" and "/lib/chart.js/" are Debian's
// /usr/share/javascript/{three,chart.js}/. Paths with "..", hidden names or control
// characters are 404.
//
// WebSockets (bearer token in the Authorization header, or for browsers, which cannot set it, in
// the subprotocols "cathbox, bearer.TOKEN"; never in the URL):
//   /api/v1/live/rigs/{rig}/stream?case=NAME[&version=N][&assignment=ID]   a rig streams
//   /api/v1/live/watch[?rigs=a,b]                                          a watcher
// Each watcher has a queue of watcher_queue messages; when a slow watcher falls behind, the
// oldest queued frames are dropped (a live view wants the newest).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "server/api.hpp"
#include "server/live_hub.hpp"
#include "server/result.hpp"
#include "server/tls.hpp"

namespace cathbox::server {

struct StaticMount {
  std::string url_prefix;  // "/", "/lib/three/"
  std::string folder;
};

struct HttpServerOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 8080;  // 0: any free port (start() answers which)
  int io_threads = 2;
  int api_threads = 4;
  int heavy_threads = 1;
  int max_heavy_queued = 32;
  std::vector<StaticMount> mounts;
  std::size_t max_header_bytes = 16 * 1024;
  int idle_timeout_s = 60;
  int body_timeout_s = 600;
  std::size_t max_connections = 4096;
  // One client address may hold at most this many of them (HTTP and WebSocket together); more
  // are closed on accept. Loopback counts as one address like any other.
  std::size_t max_connections_per_address = 256;
  // WebSockets, on the server's clock (ServerConfig::clock), looked at every sweep_every_ms
  // (0: only when sweep() is called, for tests in virtual time):
  // - an open WebSocket's token is checked again every ws_recheck_s: logged out, expired or
  //   disabled closes the socket (1008 policy violation);
  // - idle for ws_idle_timeout_s (no message either way, counted from the upgrade; pings do
  //   not count) closes a rig's stream (its rig name is released) and a trainee's watcher that
  //   watches no rig (1001 "idle");
  //   an instructor's watcher and a watcher of rigs stay however quiet the rigs are;
  // - one account holds at most max_websockets_per_account of them (more: 429 on the upgrade).
  int ws_recheck_s = 10;
  int ws_idle_timeout_s = 60;
  std::size_t max_websockets_per_account = 16;
  int sweep_every_ms = 1000;
  std::size_t watcher_queue = 64;
  std::optional<TlsFiles> tls;  // HTTPS and wss:// (server/tls.hpp); none: plain HTTP
  bool insecure_http = false;   // allow plain HTTP on a non-loopback address (behind a TLS proxy)
};

struct HttpServerStats {
  std::uint64_t connections = 0;
  std::uint64_t requests = 0;
  std::uint64_t publishers = 0;
  std::uint64_t watchers = 0;
  std::uint64_t frames_in = 0;
  std::uint64_t frames_out = 0;
  std::uint64_t frames_dropped = 0;  // slow watchers
};

class HttpServer {
 public:
  HttpServer(Api& api, LiveHub& hub, HttpServerOptions options);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Binds, listens and starts the threads; the bound port. Errors: 400 a bad option (address,
  // TLS files, plain HTTP off loopback), 503 the address cannot be bound.
  [[nodiscard]] Result<std::uint16_t> start();
  // Stops accepting, closes every connection, joins the threads (idempotent).
  void stop();
  // Reads the certificate and key files again: new connections get them, open ones (live
  // sessions included) keep theirs. On error the old certificate stays.
  [[nodiscard]] Status reload_tls();
  [[nodiscard]] bool tls() const;
  [[nodiscard]] HttpServerStats stats() const;
  // Looks at every open WebSocket now (idle eviction, token recheck); runs by itself every
  // sweep_every_ms. Each socket is judged on its own I/O thread at this call's time (one whose
  // handshake is still being answered, when it completes); a socket is seen from its upgrade.
  void sweep();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// The mounts for a web root and Debian's JavaScript libraries.
[[nodiscard]] std::vector<StaticMount> default_mounts(const std::string& web_root);

}  // namespace cathbox::server
