// TLS between cathbox-server and its client library, with a throwaway CA made by the `openssl`
// command: a good certificate (HTTPS, HSTS, wss://), the wrong host, an expired one, an untrusted
// one, plain HTTP to the TLS port and TLS to a plain port, a reload that keeps live sockets, the
// protocol floor, and the refusal of plain HTTP off loopback.
#include <boost/asio/ip/tcp.hpp>
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <vector>

#include "server/tls.hpp"
#include "server/testing/child_process.hpp"
#include "server/testing/test_ca.hpp"
#include "support/server_fixture.hpp"

namespace cathbox::server {
namespace {

using test::RunningServer;
using test::ServerOptions;
using testing::TestCa;

class TlsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    folder_ = new std::string(test::temp_folder());
    ca_ = new TestCa(*folder_, "centre-ca");
    other_ca_ = new TestCa(*folder_, "other-ca");
  }
  void TearDown() override { set_client_ca_file(""); }

  static RunningServer serve(const TlsFiles& files, const std::string& url_host = "127.0.0.1") {
    ServerOptions o;
    o.tls = files;
    o.url_host = url_host;
    return RunningServer("sqlite", o);
  }

  static inline std::string* folder_ = nullptr;
  static inline TestCa* ca_ = nullptr;
  static inline TestCa* other_ca_ = nullptr;
};

TEST_F(TlsTest, AGoodCertificateServesHttpsWithHstsAndWss) {
  RunningServer server = serve(ca_->issue("good", "DNS:localhost,IP:127.0.0.1"));
  set_client_ca_file(ca_->ca_file());
  ASSERT_EQ(server.base_url().rfind("https://", 0), 0U);
  const std::string token = server.token_for("ada", Role::kInstructor);  // a login over TLS
  HttpClient http(server.base_url());
  http.set_token(token);
  const HttpAnswer me = http.get("/api/v1/me");
  ASSERT_EQ(me.status, 200) << me.problem();
  EXPECT_EQ(me.header("strict-transport-security"), "max-age=31536000");
  EXPECT_EQ(http.get("/").status, 200);
  WsClient ws(5000);
  ASSERT_TRUE(ws.connect(server.base_url(), "/api/v1/live/watch", token));
  const Result<std::string> first = ws.read(5000);
  ASSERT_TRUE(first) << first.error().message;
  EXPECT_NE(first->find("\"rigs\""), std::string::npos);
  // The same certificate by name.
  HttpClient by_name("https://localhost:" + std::to_string(server.port()));
  EXPECT_EQ(by_name.get("/").status, 200);
}

TEST_F(TlsTest, AWrongHostIsOneLineAndNoFallback) {
  RunningServer server = serve(ca_->issue("elsewhere", "DNS:elsewhere.example"), "localhost");
  set_client_ca_file(ca_->ca_file());
  HttpClient http(server.base_url());
  const HttpAnswer a = http.get("/");
  EXPECT_EQ(a.status, 0);
  EXPECT_EQ(a.error, "TLS to localhost:" + std::to_string(server.port()) +
                         ": certificate verify failed: hostname mismatch (trusting --ca-file " + ca_->ca_file() + ")");
  HttpClient by_ip("https://127.0.0.1:" + std::to_string(server.port()));
  EXPECT_NE(by_ip.get("/").error.find("certificate verify failed: IP address mismatch"), std::string::npos);
  WsClient ws(5000);
  const Status s = ws.connect(server.base_url(), "/api/v1/live/watch", "x");
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("hostname mismatch"), std::string::npos) << s.error().message;
}

TEST_F(TlsTest, AnExpiredCertificateIsRefused) {
  RunningServer server = serve(ca_->issue("expired", "DNS:localhost,IP:127.0.0.1", -1));
  set_client_ca_file(ca_->ca_file());
  HttpClient http(server.base_url());
  const HttpAnswer a = http.get("/");
  EXPECT_EQ(a.status, 0);
  EXPECT_NE(a.error.find("certificate verify failed: certificate has expired"), std::string::npos) << a.error;
}

TEST_F(TlsTest, AnUntrustedCertificateIsRefusedWhateverStoreIsUsed) {
  RunningServer server = serve(other_ca_->issue("untrusted", "DNS:localhost,IP:127.0.0.1"));
  set_client_ca_file(ca_->ca_file());
  HttpClient http(server.base_url());
  const HttpAnswer a = http.get("/");
  EXPECT_EQ(a.status, 0);
  EXPECT_NE(a.error.find("certificate verify failed: unable to get local issuer certificate"), std::string::npos) << a.error;
  // The system store does not know a throwaway CA either, nor a self-signed certificate.
  set_client_ca_file("");
  HttpClient system(server.base_url());
  EXPECT_NE(system.get("/").error.find("certificate verify failed"), std::string::npos);
  RunningServer self_signed = serve(TlsFiles{other_ca_->ca_file(), other_ca_->ca_key()});
  set_client_ca_file(ca_->ca_file());
  HttpClient to_self_signed(self_signed.base_url());
  EXPECT_NE(to_self_signed.get("/").error.find("certificate verify failed: self-signed certificate"), std::string::npos)
      << to_self_signed.get("/").error;
  // A CA file that is not one.
  set_client_ca_file(*folder_ + "/no-such-ca.pem");
  HttpClient no_file(server.base_url());
  EXPECT_EQ(no_file.get("/").error, "--ca-file " + *folder_ + "/no-such-ca.pem: not a readable PEM certificate file");
}

TEST_F(TlsTest, PlainHttpToTheTlsPortIsToldSoAndTlsToAPlainPortFailsClearly) {
  RunningServer server = serve(ca_->issue("good2", "IP:127.0.0.1"));
  HttpClient plain("http://127.0.0.1:" + std::to_string(server.port()));
  const HttpAnswer a = plain.get("/api/v1/me");
  EXPECT_EQ(a.status, 400);
  EXPECT_EQ(a.problem(), "this port speaks HTTPS: use https://");
  EXPECT_TRUE(a.header("strict-transport-security").empty());

  RunningServer plain_server("sqlite");
  set_client_ca_file(ca_->ca_file());
  HttpClient tls_to_plain("https://127.0.0.1:" + std::to_string(plain_server.port()));
  const HttpAnswer b = tls_to_plain.get("/");
  EXPECT_EQ(b.status, 0);
  EXPECT_NE(b.error.find("TLS to 127.0.0.1:"), std::string::npos) << b.error;
  EXPECT_NE(b.error.find("plain HTTP"), std::string::npos) << b.error;
}

TEST_F(TlsTest, AReloadServesTheNewCertificateAndKeepsOpenSockets) {
  const std::string cert = *folder_ + "/served.pem", key = *folder_ + "/served.key";
  const TlsFiles first = ca_->issue("first", "IP:127.0.0.1");
  std::filesystem::copy_file(first.cert_file, cert, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(first.key_file, key, std::filesystem::copy_options::overwrite_existing);
  RunningServer server = serve(TlsFiles{cert, key});
  set_client_ca_file(ca_->ca_file());
  const std::string token = server.token_for("ada", Role::kInstructor);
  WsClient ws(5000);
  ASSERT_TRUE(ws.connect(server.base_url(), "/api/v1/live/watch", token));
  ASSERT_TRUE(ws.read(5000));

  // A broken pair is refused and the old certificate stays.
  const TlsFiles second = other_ca_->issue("second", "IP:127.0.0.1");
  std::filesystem::copy_file(second.cert_file, cert, std::filesystem::copy_options::overwrite_existing);
  const Status broken = server.app->http().reload_tls();
  ASSERT_FALSE(broken);
  EXPECT_EQ(broken.error().message, "--tls-key " + key + ": does not match the certificate in " + cert);
  EXPECT_EQ(HttpClient(server.base_url()).get("/").status, 200);

  std::filesystem::copy_file(second.key_file, key, std::filesystem::copy_options::overwrite_existing);
  ASSERT_TRUE(server.app->http().reload_tls());
  EXPECT_NE(HttpClient(server.base_url()).get("/").error.find("unable to get local issuer certificate"), std::string::npos);
  set_client_ca_file(other_ca_->ca_file());
  EXPECT_EQ(HttpClient(server.base_url()).get("/").status, 200);
  // The watcher opened before the reload still talks (a bad message gets its error line back).
  ASSERT_TRUE(ws.send("not json"));
  const Result<std::string> answer = ws.read(5000);
  ASSERT_TRUE(answer) << answer.error().message;
  EXPECT_NE(answer->find("\"error\""), std::string::npos);
}

// openssl s_client against the server; its exit code.
int s_client(std::uint16_t port, const std::string& options) {
  return testing::run_process({"/bin/sh", "-c", "openssl s_client -connect 127.0.0.1:" + std::to_string(port) + " " + options +
                                                        " </dev/null >/dev/null 2>&1"});
}

TEST_F(TlsTest, OnlyTls12And13WithForwardSecretAeadSuites) {
  RunningServer server = serve(ca_->issue("floor", "IP:127.0.0.1"));
  EXPECT_EQ(s_client(server.port(), "-tls1_3"), 0);
  EXPECT_EQ(s_client(server.port(), "-tls1_2 -cipher ECDHE-ECDSA-AES128-GCM-SHA256"), 0);
  EXPECT_NE(s_client(server.port(), "-tls1_1 -cipher ALL:@SECLEVEL=0"), 0);
  EXPECT_NE(s_client(server.port(), "-tls1_2 -cipher ECDHE-ECDSA-AES128-SHA"), 0);  // CBC
  EXPECT_NE(s_client(server.port(), "-tls1_2 -cipher AES128-GCM-SHA256"), 0);       // no forward secrecy
}

TEST_F(TlsTest, PlainHttpOffLoopbackNeedsInsecureHttpAndMissingFilesAreNamed) {
  ServerConfig config;
  config.db_url = test::fresh_database_url("sqlite");
  config.http.host = "0.0.0.0";
  config.http.port = 0;
  config.argon2 = test_argon2_params();
  Result<std::unique_ptr<ServerApp>> refused = ServerApp::start(std::move(config));
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().status, 400);  // cathbox-server exits 2 (bad input)
  EXPECT_NE(refused.error().message.find("--listen 0.0.0.0: not a loopback address, and no --tls-cert/--tls-key"), std::string::npos)
      << refused.error().message;

  ServerConfig missing;
  missing.db_url = test::fresh_database_url("sqlite");
  missing.http.port = 0;
  missing.http.tls = TlsFiles{*folder_ + "/absent.pem", *folder_ + "/absent.key"};
  missing.argon2 = test_argon2_params();
  Result<std::unique_ptr<ServerApp>> no_file = ServerApp::start(std::move(missing));
  ASSERT_FALSE(no_file);
  EXPECT_EQ(no_file.error().status, 400);
  EXPECT_EQ(no_file.error().message, "--tls-cert " + *folder_ + "/absent.pem: cannot read: No such file or directory");

  ServerConfig insecure;
  insecure.db_url = test::fresh_database_url("sqlite");
  insecure.http.host = "0.0.0.0";
  insecure.http.port = 0;
  insecure.http.insecure_http = true;
  insecure.argon2 = test_argon2_params();
  Result<std::unique_ptr<ServerApp>> started = ServerApp::start(std::move(insecure));
  ASSERT_TRUE(started) << started.error().message;
  started.value()->stop();
}

// The per-address cap counts a connection from its accept, before the TLS handshake: an address
// holding its share with sockets that never say a byte gets no further connection (not even the
// plain-HTTP "use https://" answer).
TEST_F(TlsTest, ThePerAddressCapCountsConnectionsBeforeTheirHandshake) {
  ServerOptions o;
  o.tls = ca_->issue("capped", "IP:127.0.0.1");
  o.max_connections_per_address = 3;
  RunningServer server("sqlite", o);
  const std::string plain = "GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
  ASSERT_EQ(test::raw_exchange(server.port(), plain).rfind("HTTP/1.1 400", 0), 0U) << "room for one: told to use https://";
  boost::asio::io_context ioc;
  const boost::asio::ip::tcp::endpoint at(boost::asio::ip::make_address("127.0.0.1"), server.port());
  std::vector<std::unique_ptr<boost::asio::ip::tcp::socket>> silent;
  for (int i = 0; i < 3; ++i) {
    silent.push_back(std::make_unique<boost::asio::ip::tcp::socket>(ioc));
    silent.back()->connect(at);
  }
  EXPECT_EQ(test::raw_exchange(server.port(), plain, 3000), "") << "a fourth from the same address is closed unanswered";
  silent.front()->close();
  std::string after;
  for (int i = 0; i < 50 && after.empty(); ++i) after = test::raw_exchange(server.port(), plain, 2000);
  EXPECT_EQ(after.rfind("HTTP/1.1 400", 0), 0U) << "room again once one is gone: " << after.substr(0, 200);
}

}  // namespace
}  // namespace cathbox::server
