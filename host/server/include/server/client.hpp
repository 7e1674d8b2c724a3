#pragma once
// The client side of cathbox-server, for the trainer (host/app), tests and the benchmark.
// Plain C++ types only: Boost.Beast stays inside host/server.
//
//   HttpClient   one keep-alive HTTP/1.1 connection, synchronous, with a timeout per request
//   WsClient     a synchronous WebSocket (tests, watchers in the benchmark)
//   ServerClient the typed API a trainer uses: login, assignments, cases, downloads, uploads
//   LiveStream   a rig's live stream: push() the newest frame, a background thread sends it,
//                reconnecting when the server goes away (never blocks the caller)
//   UploadQueue  finished records on disk until the server has them (client_queue.hpp)
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "server/result.hpp"

namespace cathbox::server {

struct HttpAnswer {
  int status = 0;       // 0: no answer (see error)
  std::string error;    // transport problem: "connect 127.0.0.1:8080: Connection refused"
  std::string body;
  std::map<std::string, std::string> headers;  // names in lower case
  [[nodiscard]] std::string header(const std::string& lower_name) const;
  // The API's {"error": "..."} line, or the transport error, or "HTTP <status>".
  [[nodiscard]] std::string problem() const;
};

using Headers = std::vector<std::pair<std::string, std::string>>;

class HttpClient {
 public:
  // base_url: "http://HOST:PORT", or "https://HOST:PORT" with the certificate checked (server/tls.hpp).
  explicit HttpClient(std::string base_url, int timeout_ms = 30000);
  ~HttpClient();
  HttpClient(const HttpClient&) = delete;
  HttpClient& operator=(const HttpClient&) = delete;

  void set_token(std::string token) { token_ = std::move(token); }
  [[nodiscard]] const std::string& token() const { return token_; }
  [[nodiscard]] HttpAnswer request(std::string_view method, std::string_view target, std::string_view body = {},
                                   const Headers& headers = {});
  // Answers with the raw bytes as received (no Content-Encoding decoding).
  [[nodiscard]] HttpAnswer get(std::string_view target) { return request("GET", target); }
  [[nodiscard]] HttpAnswer post_json(std::string_view target, std::string_view json) {
    return request("POST", target, json, {{"Content-Type", "application/json"}});
  }
  void close();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  std::string token_;
};

class WsClient {
 public:
  explicit WsClient(int timeout_ms = 30000);
  ~WsClient();
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;
  // url: "http://HOST:PORT"; target: "/api/v1/live/watch?rigs=a". The handshake's HTTP status
  // is in the error when refused ("HTTP 403: ...").
  [[nodiscard]] Status connect(const std::string& base_url, const std::string& target, const std::string& token);
  [[nodiscard]] Status send(std::string_view text);
  // The next text message; or, on timeout, the error `kReadTimeout` (status 408: the read stays
  // pending and the socket open, so read again); or the closed/failed socket's line.
  [[nodiscard]] Result<std::string> read(int timeout_ms);
  static constexpr const char* kReadTimeout = "timeout";
  void close();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

struct CaseInfo {
  std::string name;
  int version = 0;
  std::string title;
  std::string content_hash;
  std::int64_t wire_bytes = 0;
  std::int64_t mesh_bytes = 0;
};

struct AssignmentInfo {
  std::int64_t id = 0;
  std::string case_name;
  int case_version = 0;  // 0: the newest
  std::string note;
  std::string criteria_json;
  std::string due_at;
};

enum class UploadVerdict {
  kStored,       // 201: new result
  kDuplicate,    // 200: the server already had this record (same content hash)
  kRefused,      // 4xx: the server will never take it (tampered, broken, wrong assignment)
  kUnauthorized, // 401: log in again, then retry
  kRetryLater    // unreachable, 5xx, 429: keep it and try again
};

struct UploadOutcome {
  UploadVerdict verdict = UploadVerdict::kRetryLater;
  std::int64_t result_id = 0;
  std::string message;  // the server's line, or the transport error
};

class ServerClient {
 public:
  explicit ServerClient(std::string base_url, int timeout_ms = 30000);
  [[nodiscard]] const std::string& base_url() const { return base_url_; }

  [[nodiscard]] Status login(const std::string& name, const std::string& password);
  void set_token(std::string token) { http_.set_token(std::move(token)); }
  [[nodiscard]] const std::string& token() const { return http_.token(); }
  [[nodiscard]] Result<std::vector<AssignmentInfo>> assignments();
  [[nodiscard]] Result<std::vector<CaseInfo>> cases();
  // Downloads a case (zstd, checked against its content hash) into folder/NAME-vVERSION/ and
  // answers the case file's path there. version 0: the newest.
  [[nodiscard]] Result<std::string> download_case(const std::string& name, int version, const std::string& folder);
  [[nodiscard]] UploadOutcome upload_record(const std::string& bytes, std::optional<std::int64_t> assignment_id);
  [[nodiscard]] HttpClient& http() { return http_; }

 private:
  std::string base_url_;
  HttpClient http_;
};

struct LiveStreamStats {
  std::uint64_t pushed = 0;
  std::uint64_t sent = 0;
  std::uint64_t replaced = 0;  // frames superseded by a newer one before they could go
  std::uint64_t connects = 0;
  std::string last_error;
};

class LiveStream {
 public:
  struct Options {
    std::string base_url;
    std::string token;
    std::string rig;
    std::string case_name;
    int case_version = 0;
    std::optional<std::int64_t> assignment_id;
    int reconnect_ms = 1000;
  };
  explicit LiveStream(Options options);
  ~LiveStream();  // sends {"type": "end"} when connected, then stops
  LiveStream(const LiveStream&) = delete;
  LiveStream& operator=(const LiveStream&) = delete;

  // Hands over the newest frame (a JSON object text with type "frame"); never blocks.
  void push(std::string frame_json);
  [[nodiscard]] LiveStreamStats stats() const;
  [[nodiscard]] bool connected() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

struct ServerUrl {
  bool tls = false;  // https://
  std::string host;
  std::string port;
};
// "http://HOST:PORT[/]" or "https://HOST:PORT[/]"; error for anything else.
[[nodiscard]] Result<ServerUrl> parse_server_url(const std::string& base_url);
// {HOST, PORT} of the same.
[[nodiscard]] Result<std::pair<std::string, std::string>> split_base_url(const std::string& base_url);

}  // namespace cathbox::server
