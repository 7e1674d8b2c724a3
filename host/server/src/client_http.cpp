// HttpClient and WsClient: synchronous calls over Beast's asynchronous operations, run on a
// private io_context so every step has a deadline.
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <nlohmann/json.hpp>

#include "server/client.hpp"
#include "tls_client.hpp"
#include "tls_or_plain_stream.hpp"

namespace cathbox::server {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

std::string HttpAnswer::header(const std::string& lower_name) const {
  const auto it = headers.find(lower_name);
  return it == headers.end() ? std::string() : it->second;
}

std::string HttpAnswer::problem() const {
  if (status == 0) return error;
  try {
    const nlohmann::json j = nlohmann::json::parse(body);
    if (j.is_object() && j.contains("error") && j["error"].is_string()) return j["error"].get<std::string>();
  } catch (const std::exception&) {
  }
  return "HTTP " + std::to_string(status);
}

Result<ServerUrl> parse_server_url(const std::string& base_url) {
  const std::string bad = "server URL '" + base_url + "': expected http://HOST:PORT or https://HOST:PORT";
  ServerUrl url;
  std::string rest;
  if (base_url.rfind("http://", 0) == 0) {
    rest = base_url.substr(7);
  } else if (base_url.rfind("https://", 0) == 0) {
    url.tls = true;
    rest = base_url.substr(8);
  } else {
    return make_error(400, bad);
  }
  while (!rest.empty() && rest.back() == '/') rest.pop_back();
  const std::size_t colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == rest.size() || rest.find('/') != std::string::npos) {
    return make_error(400, bad);
  }
  url.host = rest.substr(0, colon);
  if (url.host.size() > 2 && url.host.front() == '[' && url.host.back() == ']') url.host = url.host.substr(1, url.host.size() - 2);
  url.port = rest.substr(colon + 1);
  return url;
}

Result<std::pair<std::string, std::string>> split_base_url(const std::string& base_url) {
  Result<ServerUrl> url = parse_server_url(base_url);
  if (!url) return url.error();
  return std::make_pair(url.value().host, url.value().port);
}

namespace {

// Runs the io_context until the started operations finish.
void run(net::io_context& ioc) {
  ioc.restart();
  ioc.run();
}

// Runs handlers until `done` (other operations, such as a pending read, may stay pending).
void run_until(net::io_context& ioc, const bool& done) {
  ioc.restart();
  while (!done && ioc.run_one() > 0) {
  }
}

beast::error_code connect_stream(net::io_context& ioc, beast::tcp_stream& stream, const std::string& host, const std::string& port,
                                 int timeout_ms) {
  beast::error_code result;
  tcp::resolver resolver(ioc);
  tcp::resolver::results_type endpoints;
  resolver.async_resolve(host, port, [&](beast::error_code ec, tcp::resolver::results_type r) {
    result = ec;
    endpoints = std::move(r);
  });
  run(ioc);
  if (result) return result;
  stream.expires_after(std::chrono::milliseconds(timeout_ms));
  stream.async_connect(endpoints, [&](beast::error_code ec, const tcp::endpoint&) { result = ec; });
  run(ioc);
  if (!result) stream.socket().set_option(tcp::no_delay(true), result);
  return result;
}

// A new connection to `url`: TCP, then for https:// the TLS handshake with the certificate
// checked. Empty on success, else the one line saying why not.
std::string open_stream(net::io_context& ioc, std::optional<TlsOrPlainStream>& stream, const ServerUrl& url, int timeout_ms) {
  std::shared_ptr<net::ssl::context> context;
  if (url.tls) {
    Result<std::shared_ptr<net::ssl::context>> made = client_tls_context();
    if (!made) return made.error().message;
    context = made.value();
  }
  beast::tcp_stream connection(ioc);
  if (beast::error_code ec = connect_stream(ioc, connection, url.host, url.port, timeout_ms)) {
    return "connect " + url.host + ":" + url.port + ": " + ec.message();
  }
  if (!url.tls) {
    stream.emplace(std::move(connection));
    return {};
  }
  stream.emplace(std::move(connection), context);
  expect_server_name(stream->tls(), url.host);
  beast::error_code result;
  stream->expires_after(std::chrono::milliseconds(timeout_ms));
  stream->tls().async_handshake(net::ssl::stream_base::client, [&](beast::error_code ec) { result = ec; });
  run(ioc);
  if (!result) return {};
  std::string line = tls_failure_line(stream->tls(), result, url.host, url.port);
  stream.reset();
  return line;
}

}  // namespace

struct HttpClient::Impl {
  ServerUrl url;
  std::string base_url;
  int timeout_ms;
  net::io_context ioc;
  std::optional<TlsOrPlainStream> stream;
  beast::flat_buffer buffer;

  // One attempt; `reused` says whether the connection was open before.
  HttpAnswer attempt(const http::request<http::string_body>& req, bool& retryable) {
    HttpAnswer out;
    retryable = false;
    const bool reused = stream.has_value();
    if (!stream) {
      buffer.clear();
      out.error = open_stream(ioc, stream, url, timeout_ms);
      if (!out.error.empty()) return out;
    }
    beast::error_code result;
    stream->expires_after(std::chrono::milliseconds(timeout_ms));
    http::async_write(*stream, req, [&](beast::error_code ec, std::size_t) { result = ec; });
    run(ioc);
    http::response_parser<http::string_body> parser;
    parser.body_limit(256ULL * 1024 * 1024);
    if (!result) {
      stream->expires_after(std::chrono::milliseconds(timeout_ms));
      http::async_read(*stream, buffer, parser, [&](beast::error_code ec, std::size_t) { result = ec; });
      run(ioc);
    }
    if (result) {
      // A kept-alive connection the server had closed: worth one more try on a new one.
      retryable = reused && (result == http::error::end_of_stream || result == net::error::eof ||
                             result == net::error::connection_reset || result == net::error::broken_pipe);
      stream.reset();
      out.error = std::string(req.method_string()) + " " + std::string(req.target()) + ": " + result.message();
      return out;
    }
    const auto& res = parser.get();
    out.status = static_cast<int>(res.result_int());
    out.body = res.body();
    for (const auto& field : res) {
      std::string name(field.name_string());
      for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      out.headers[name] = std::string(field.value());
    }
    if (!res.keep_alive()) stream.reset();
    return out;
  }
};

HttpClient::HttpClient(std::string base_url, int timeout_ms) : impl_(std::make_unique<Impl>()) {
  impl_->base_url = base_url;
  impl_->timeout_ms = timeout_ms;
  const auto parsed = parse_server_url(base_url);
  if (parsed) impl_->url = parsed.value();
}

HttpClient::~HttpClient() = default;

void HttpClient::close() { impl_->stream.reset(); }

HttpAnswer HttpClient::request(std::string_view method, std::string_view target, std::string_view body, const Headers& headers) {
  if (impl_->url.host.empty()) {
    HttpAnswer bad;
    bad.error = parse_server_url(impl_->base_url).error().message;
    return bad;
  }
  http::request<http::string_body> req;
  req.method_string(beast::string_view(method.data(), method.size()));
  req.target(beast::string_view(target.data(), target.size()));
  req.version(11);
  req.set(http::field::host, impl_->url.host + ":" + impl_->url.port);
  req.set(http::field::user_agent, "cathbox-client");
  if (!token_.empty()) req.set(http::field::authorization, "Bearer " + token_);
  for (const auto& [name, value] : headers) req.set(name, value);
  req.body() = std::string(body);
  req.keep_alive(true);
  req.prepare_payload();
  bool retryable = false;
  HttpAnswer a = impl_->attempt(req, retryable);
  if (retryable) a = impl_->attempt(req, retryable);
  return a;
}

// ---- WsClient -------------------------------------------------------------------------------

struct WsClient::Impl {
  int timeout_ms;
  net::io_context ioc;
  std::optional<websocket::stream<TlsOrPlainStream>> ws;
  beast::flat_buffer buffer;
  // A read that outlived its call's timeout stays pending; the next read() collects it.
  bool reading = false;
  bool read_done = false;
  beast::error_code read_result;
};

WsClient::WsClient(int timeout_ms) : impl_(std::make_unique<Impl>()) { impl_->timeout_ms = timeout_ms; }
WsClient::~WsClient() { close(); }

Status WsClient::connect(const std::string& base_url, const std::string& target, const std::string& token) {
  const auto parsed = parse_server_url(base_url);
  if (!parsed) return parsed.error();
  const std::string& host = parsed.value().host;
  const std::string& port = parsed.value().port;
  close();
  std::optional<TlsOrPlainStream> stream;
  if (std::string problem = open_stream(impl_->ioc, stream, parsed.value(), impl_->timeout_ms); !problem.empty()) {
    return make_error(503, problem);
  }
  impl_->ws.emplace(std::move(*stream));
  auto& lowest = beast::get_lowest_layer(*impl_->ws);
  impl_->ws->set_option(websocket::stream_base::decorator([token](websocket::request_type& req) {
    req.set(http::field::user_agent, "cathbox-client");
    if (!token.empty()) req.set(http::field::authorization, "Bearer " + token);
  }));
  impl_->ws->read_message_max(64ULL * 1024 * 1024);
  websocket::response_type res;
  beast::error_code result;
  lowest.expires_after(std::chrono::milliseconds(impl_->timeout_ms));
  impl_->ws->async_handshake(res, host + ":" + port, target, [&](beast::error_code ec) { result = ec; });
  run(impl_->ioc);
  if (result) {
    impl_->ws.reset();
    if (res.result_int() != 0 && res.result_int() != 101) {
      std::string line = res.body();
      try {
        line = nlohmann::json::parse(res.body()).at("error").get<std::string>();
      } catch (const std::exception&) {
      }
      return make_error(static_cast<int>(res.result_int()), "HTTP " + std::to_string(res.result_int()) + ": " + line);
    }
    return make_error(503, "websocket " + target + ": " + result.message());
  }
  lowest.expires_never();
  return Ok{};
}

Status WsClient::send(std::string_view text) {
  if (!impl_->ws) return make_error(503, "websocket: not connected");
  beast::error_code result;
  bool done = false;
  impl_->ws->text(true);
  impl_->ws->async_write(net::buffer(text.data(), text.size()), [&](beast::error_code ec, std::size_t) {
    result = ec;
    done = true;
  });
  run_until(impl_->ioc, done);
  if (result) return make_error(503, "websocket send: " + result.message());
  return Ok{};
}

Result<std::string> WsClient::read(int timeout_ms) {
  Impl& m = *impl_;
  if (!m.ws) return make_error(503, "not connected");
  if (!m.reading) {
    m.reading = true;
    m.read_done = false;
    m.ws->async_read(m.buffer, [&m](beast::error_code ec, std::size_t) {
      m.read_result = ec;
      m.read_done = true;
    });
  }
  if (!m.read_done) {
    m.ioc.restart();
    m.ioc.run_for(std::chrono::milliseconds(timeout_ms));
  }
  if (!m.read_done) return make_error(408, kReadTimeout);
  m.reading = false;
  if (m.read_result) {
    Error closed = make_error(503, m.read_result.message());
    m.ws.reset();
    return closed;
  }
  std::string text = beast::buffers_to_string(m.buffer.data());
  m.buffer.consume(m.buffer.size());
  return text;
}

void WsClient::close() {
  if (!impl_->ws) return;
  bool done = false;
  beast::get_lowest_layer(*impl_->ws).expires_after(std::chrono::milliseconds(1000));
  impl_->ws->async_close(websocket::close_code::normal, [&](beast::error_code) { done = true; });
  run_until(impl_->ioc, done);
  // Let a pending read finish (it completes with the close), then drop the stream.
  beast::get_lowest_layer(*impl_->ws).cancel();
  run(impl_->ioc);
  impl_->reading = false;
  impl_->ws.reset();
}

}  // namespace cathbox::server
