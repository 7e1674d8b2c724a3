#pragma once
// One stream type for both kinds of connection, so the HTTP and WebSocket code is written once:
// a Beast TCP stream, or Beast's SSL stream over one. Read and write go to whichever it holds;
// next_layer() is always the TCP stream (deadlines, the socket), so get_lowest_layer() works.
// The WebSocket teardown overloads below (found by argument-dependent lookup) close either kind.
// Private to host/server: server and client both use it.
#include <memory>
#include <optional>
#include <utility>

#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <boost/beast/websocket/teardown.hpp>

namespace cathbox::server {

class TlsOrPlainStream {
 public:
  using TcpStream = boost::beast::tcp_stream;
  using TlsStream = boost::beast::ssl_stream<TcpStream>;
  using executor_type = TcpStream::executor_type;
  using next_layer_type = TcpStream;

  // Plain.
  explicit TlsOrPlainStream(TcpStream&& tcp) : plain_(std::move(tcp)) {}
  // TLS over `tcp` with `context` (kept alive by this stream: a reload does not pull it away).
  TlsOrPlainStream(TcpStream&& tcp, std::shared_ptr<boost::asio::ssl::context> context)
      : context_(std::move(context)), tls_(std::in_place, std::move(tcp), *context_) {}

  [[nodiscard]] bool is_tls() const { return tls_.has_value(); }
  [[nodiscard]] TlsStream& tls() { return *tls_; }
  [[nodiscard]] TcpStream& next_layer() { return tls_ ? tls_->next_layer() : *plain_; }
  [[nodiscard]] const TcpStream& next_layer() const { return tls_ ? tls_->next_layer() : *plain_; }
  [[nodiscard]] executor_type get_executor() { return next_layer().get_executor(); }
  template <class Duration>
  void expires_after(Duration d) {
    next_layer().expires_after(d);
  }

  template <class Buffers, class Handler>
  auto async_read_some(const Buffers& buffers, Handler&& handler) {
    if (tls_) return tls_->async_read_some(buffers, std::forward<Handler>(handler));
    return plain_->async_read_some(buffers, std::forward<Handler>(handler));
  }
  template <class Buffers, class Handler>
  auto async_write_some(const Buffers& buffers, Handler&& handler) {
    if (tls_) return tls_->async_write_some(buffers, std::forward<Handler>(handler));
    return plain_->async_write_some(buffers, std::forward<Handler>(handler));
  }

  friend void teardown(boost::beast::role_type role, TlsOrPlainStream& s, boost::beast::error_code& ec) {
    using boost::beast::websocket::teardown;
    if (s.tls_) return teardown(role, *s.tls_, ec);
    teardown(role, *s.plain_, ec);
  }
  template <class Handler>
  friend void async_teardown(boost::beast::role_type role, TlsOrPlainStream& s, Handler&& handler) {
    using boost::beast::websocket::async_teardown;
    if (s.tls_) return async_teardown(role, *s.tls_, std::forward<Handler>(handler));
    async_teardown(role, *s.plain_, std::forward<Handler>(handler));
  }

 private:
  std::optional<TcpStream> plain_;
  std::shared_ptr<boost::asio::ssl::context> context_;
  std::optional<TlsStream> tls_;
};

}  // namespace cathbox::server
