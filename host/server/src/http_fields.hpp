#pragma once
// The pieces of an HTTP exchange every session shares: the security headers of every answer, the
// bearer token a browser's WebSocket offers, a file's content type, a Beast request as the API's
// request, the answer to a failed authentication.

#include <filesystem>
#include <string>
#include <string_view>

#include <boost/beast/http.hpp>

#include "server/api.hpp"

namespace cathbox::server {

inline std::string_view sv(boost::beast::string_view s) { return {s.data(), s.size()}; }

// Every answer, API or page: the pages run only their own scripts and modules (no inline
// script, no eval, no other origin; WebAssembly compiled from their own files), are never
// framed, and no type is sniffed. The one other place a page may connect to: a box bridge on
// this machine's loopback (cathbox-box-bridge, /train.html?box=ws://127.0.0.1:PORT). Cross-origin isolated (COOP + COEP): the trainee page's
// WebAssembly session shares memory with its threads (SharedArrayBuffer).
void security_headers(boost::beast::http::response<boost::beast::http::string_body>& res);

// "bearer.TOKEN" out of a Sec-WebSocket-Protocol list ("cathbox, bearer.TOKEN"); empty if none.
std::string bearer_from_subprotocols(std::string_view list);

std::string content_type_for(const std::filesystem::path& p);

ApiRequest to_api_request(const boost::beast::http::request<boost::beast::http::string_body>& req, const std::string& remote);

// An error answer for a failed authentication; a 401 names the scheme (RFC 9110 section 11.6.1).
ApiResponse auth_refusal(const Error& e);

}  // namespace cathbox::server
