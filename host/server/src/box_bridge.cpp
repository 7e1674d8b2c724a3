#include "server/box_bridge.hpp"

#include <unistd.h>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/websocket.hpp>
#include <cstdio>
#include <deque>
#include <memory>

#include "device/socket_transport.hpp"
#include "protocol/cbx_protocol.h"

namespace cathbox::server {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

// One page's connection: the WebSocket and its own connection to the emulator. Everything runs
// on the bridge's one thread; the object lives while an asynchronous operation holds it.
class PageLink : public std::enable_shared_from_this<PageLink> {
 public:
  PageLink(tcp::socket socket, std::unique_ptr<device::SocketTransport> box, BoxBridgeCounts& counts,
           std::function<void()> closed)
      : ws_(std::move(socket)),
        box_(std::move(box)),
        box_fd_(ws_.get_executor(), ::dup(box_->fd())),
        counts_(counts),
        closed_(std::move(closed)) {}
  PageLink(const PageLink&) = delete;
  PageLink& operator=(const PageLink&) = delete;
  ~PageLink() { closed_(); }

  void start() {
    ws_.binary(true);
    ws_.read_message_max(4096);
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.async_accept([self = shared_from_this()](beast::error_code ec) {
      if (ec) return self->fail("WebSocket handshake", ec);
      std::fprintf(stderr, "box-bridge: a page connected to %s\n", self->box_->describe().c_str());
      self->read_page();
      self->wait_box();
    });
  }

 private:
  void fail(const char* what, beast::error_code ec) {
    if (ec != websocket::error::closed && ec != asio::error::operation_aborted && ec != asio::error::eof)
      std::fprintf(stderr, "box-bridge: %s: %s\n", what, ec.message().c_str());
    stop();
  }

  void stop() {
    if (stopped_) return;
    stopped_ = true;
    beast::error_code ignored;
    box_fd_.cancel(ignored);
    box_fd_.close(ignored);
    beast::get_lowest_layer(ws_).cancel(ignored);
  }

  // A refused message: one line, and the page's connection closes with the same reason.
  void refuse(const std::string& why) {
    ++counts_.refused;
    std::fprintf(stderr, "box-bridge: refused %s\n", why.c_str());
    stopped_ = true;
    beast::error_code ignored;
    box_fd_.cancel(ignored);
    box_fd_.close(ignored);
    ws_.async_close(websocket::close_reason(websocket::close_code::policy_error, why),
                    [self = shared_from_this()](beast::error_code) {});
  }

  void read_page() {
    ws_.async_read(rx_, [self = shared_from_this()](beast::error_code ec, std::size_t size) {
      if (ec) return self->fail("page", ec);
      if (self->stopped_) return;
      if (!self->ws_.got_binary()) return self->refuse("a text message (reports are binary)");
      if (size == 1) {  // GET_REPORT of a feature report
        std::uint8_t id = 0;
        asio::buffer_copy(asio::buffer(&id, 1), self->rx_.data());
        self->rx_.consume(size);
        self->answer_feature(id);
        return self->read_page();
      }
      if (size != device::kReportSize) {
        return self->refuse("a " + std::to_string(size) + "-byte message (a report is " +
                            std::to_string(device::kReportSize) + " bytes, a feature request 1)");
      }
      device::Report report{};
      asio::buffer_copy(asio::buffer(report), self->rx_.data());
      self->rx_.consume(size);
      const device::IoStatus io = self->box_->write_out(report);
      if (io == device::IoStatus::kOk) ++self->counts_.out_reports;
      else if (io == device::IoStatus::kEmpty) ++self->counts_.out_dropped;
      else return self->box_gone();
      self->read_page();
    });
  }

  // The box's answer to GET_REPORT(id) on its control endpoint (the IN reports that arrive
  // meanwhile are kept by the transport), or the ID alone when it refused.
  void answer_feature(std::uint8_t id) {
    ++counts_.features;
    Message answer;
    const device::Status got = box_->get_feature(id, answer.bytes);
    if (!got) {
      std::fprintf(stderr, "box-bridge: feature report 0x%02x: %s\n", id, got.error().message.c_str());
      answer.bytes[0] = id;
      answer.size = 1;
    }
    send_page(answer);
  }

  void box_gone() {
    std::fprintf(stderr, "box-bridge: the box went away (%s)\n", box_->describe().c_str());
    stopped_ = true;
    beast::error_code ignored;
    box_fd_.cancel(ignored);
    box_fd_.close(ignored);
    ws_.async_close(websocket::close_reason(websocket::close_code::going_away, "the box went away"),
                    [self = shared_from_this()](beast::error_code) {});
  }

  void wait_box() {
    box_fd_.async_wait(asio::posix::stream_descriptor::wait_read, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return self->fail("box", ec);
      if (self->stopped_) return;
      device::Report report{};
      for (;;) {
        const device::IoStatus io = self->box_->read_in(report);
        if (io == device::IoStatus::kEmpty) break;
        if (io == device::IoStatus::kDisconnected) return self->box_gone();
        self->send_page(Message{report, device::kReportSize});
      }
      self->wait_box();
    });
  }

  // A message to the page: a report, or a refused feature request's ID alone.
  struct Message {
    device::Report bytes{};
    std::size_t size = device::kReportSize;
  };

  // IN reports queue behind the one being written; a page that does not keep up loses the
  // oldest (a USB host that does not poll loses IN reports the same way).
  void send_page(const Message& message) {
    static constexpr std::size_t kMaxQueued = 64;
    if (tx_.size() >= kMaxQueued) tx_.erase(tx_.begin() + 1);
    tx_.push_back(message);
    if (tx_.size() == 1) write_next();
  }

  void write_next() {
    ws_.async_write(asio::buffer(tx_.front().bytes.data(), tx_.front().size), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->fail("page", ec);
      if (self->tx_.front().bytes[0] == CBX_ID_STATE) ++self->counts_.in_reports;
      self->tx_.pop_front();
      if (!self->tx_.empty() && !self->stopped_) self->write_next();
    });
  }

  websocket::stream<tcp::socket> ws_;
  std::unique_ptr<device::SocketTransport> box_;
  asio::posix::stream_descriptor box_fd_;
  BoxBridgeCounts& counts_;
  std::function<void()> closed_;
  beast::flat_buffer rx_;
  std::deque<Message> tx_;
  bool stopped_ = false;
};

class Bridge {
 public:
  Bridge(asio::io_context& io, tcp::acceptor& acceptor, const BoxBridgeOptions& options)
      : io_(io), acceptor_(acceptor), options_(options) {}

  void accept() {
    acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
      if (ec) {
        std::fprintf(stderr, "box-bridge: accept: %s\n", ec.message().c_str());
        return accept();
      }
      serve(std::move(socket));
    });
  }

 private:
  // One page at a time: the next accept starts when this page's link is gone.
  void serve(tcp::socket socket) {
    const std::string path = options_.emu_socket.empty() ? device::SocketTransport::default_path() : options_.emu_socket;
    auto box = device::SocketTransport::open(path, clock_);
    if (!box) {
      std::fprintf(stderr, "box-bridge: %s\n", box.error().message.c_str());
      // The page learns why from the close reason of a connection that is accepted, then closed.
      auto ws = std::make_shared<websocket::stream<tcp::socket>>(std::move(socket));
      const std::string why = box.error().message.substr(0, 120);  // a close reason holds 123 bytes
      ws->async_accept([this, ws, why](beast::error_code ec) {
        if (ec) return accept();
        ws->async_close(websocket::close_reason(websocket::close_code::try_again_later, why),
                        [this, ws](beast::error_code) { accept(); });
      });
      return;
    }
    ++counts_.pages;
    std::make_shared<PageLink>(std::move(socket), std::move(*box), counts_, [this] {
      std::fprintf(stderr, "box-bridge: page closed (%llu IN, %llu OUT, %llu OUT dropped, %llu features, %llu refused so far)\n",
                   static_cast<unsigned long long>(counts_.in_reports),
                   static_cast<unsigned long long>(counts_.out_reports),
                   static_cast<unsigned long long>(counts_.out_dropped),
                   static_cast<unsigned long long>(counts_.features),
                   static_cast<unsigned long long>(counts_.refused));
      asio::post(io_, [this] { accept(); });
    })->start();
  }

  asio::io_context& io_;
  tcp::acceptor& acceptor_;
  const BoxBridgeOptions& options_;
  device::SystemClock clock_;
  BoxBridgeCounts counts_;
};

}  // namespace

int run_box_bridge(const BoxBridgeOptions& options, const std::function<void(std::uint16_t)>& ready) {
  asio::io_context io;
  beast::error_code ec;
  const auto address = asio::ip::make_address(options.address, ec);
  if (ec) {
    std::fprintf(stderr, "box-bridge: --listen %s: not an IP address\n", options.address.c_str());
    return 2;
  }
  tcp::acceptor acceptor(io);
  const tcp::endpoint endpoint(address, options.port);
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) {
    std::fprintf(stderr, "box-bridge: cannot listen on %s:%u: %s\n", options.address.c_str(),
                 static_cast<unsigned>(options.port), ec.message().c_str());
    return 2;
  }
  Bridge bridge(io, acceptor, options);
  bridge.accept();
  ready(acceptor.local_endpoint().port());
  io.run();
  return 0;
}

}  // namespace cathbox::server
