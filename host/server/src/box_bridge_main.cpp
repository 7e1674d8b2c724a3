// cathbox-box-bridge [--port N] [--listen ADDR] [--emu-socket PATH]: the emulated box on a
// WebSocket (server/box_bridge.hpp). Prints "box-bridge: ws://ADDR:PORT" once listening.
// Exit codes: 0 stopped, 1 bad arguments, 2 cannot listen.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "server/box_bridge.hpp"

int main(int argc, char** argv) {
  cathbox::server::BoxBridgeOptions options;
  CLI::App app{"cathbox-box-bridge: cathbox-emu's box on a WebSocket (one 64-byte report a message)"};
  app.add_option("--port", options.port, "TCP port (0: any free port, printed)");
  app.add_option("--listen", options.address, "address to listen on (default loopback only)");
  app.add_option("--emu-socket", options.emu_socket, "cathbox-emu's socket (default: its default path)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;
  }
  return cathbox::server::run_box_bridge(options, [&options](std::uint16_t port) {
    std::printf("box-bridge: ws://%s:%u\n", options.address.c_str(), static_cast<unsigned>(port));
    std::fflush(stdout);
  });
}
