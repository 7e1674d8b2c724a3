#pragma once
// TLS for cathbox-server and its clients (OpenSSL through Boost.Asio; the header keeps both out
// of its users).
//
// Server: a PEM certificate chain and its private key (--tls-cert, --tls-key). TLS 1.2 and 1.3
// only; TLS 1.2 with forward-secret AEAD suites only (ECDHE with AES-GCM or ChaCha20-Poly1305);
// no renegotiation, no compression. The files are read again on HttpServer::reload_tls()
// (SIGHUP): new connections get the new certificate, open ones keep theirs.
//
// Client (HttpClient, WsClient, ServerClient, LiveStream): "https://HOST:PORT" URLs verify the
// server's certificate against the system's trust store, or against the one PEM file given to
// set_client_ca_file(), and check that it names HOST (DNS name or IP address). A failure is one
// line ("TLS to HOST:PORT: certificate verify failed: hostname mismatch ..."); there is never a
// fallback to plain HTTP.
#include <string>

namespace cathbox::server {

struct TlsFiles {
  std::string cert_file;  // PEM, the server's certificate then its intermediates
  std::string key_file;   // PEM, unencrypted
};

// Process-wide: the CA file every client in this process trusts ("" = the system trust store).
// Set once at start (the trainer's --ca-file), before any client connects.
void set_client_ca_file(std::string pem_path);
[[nodiscard]] std::string client_ca_file();

}  // namespace cathbox::server
