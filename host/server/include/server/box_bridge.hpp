#pragma once
// cathbox-box-bridge: the emulated box (cathbox-emu's socket) on a WebSocket, so that a page's
// box path (js/box_transport.js) runs against cathbox-emu where a real box would be on WebHID.
// Each binary WebSocket message is one 64-byte report with the same bytes as USB: IN (state)
// reports from the box to the page, OUT (command) reports from the page to the box. A feature
// report is asked for as USB's GET_REPORT is: the page sends its one-byte ID, the bridge asks the
// box on its control endpoint and sends the 64-byte answer (the ID at byte 0), or the ID alone
// when the box refused it (STALL). Feature reports are never set through the bridge. One page at
// a time: a second connection waits until the first one closed. A message of another size is
// refused (the connection is closed, one line on stderr names its length); the box's OUT queue
// being full drops the report, as USB does.
#include <cstdint>
#include <functional>
#include <string>

namespace cathbox::server {

struct BoxBridgeOptions {
  std::string address = "127.0.0.1";  // loopback only unless asked
  std::uint16_t port = 0;             // 0: any free port (printed)
  std::string emu_socket;             // cathbox-emu's socket; empty: the default path
};

struct BoxBridgeCounts {
  std::uint64_t pages = 0;         // WebSocket connections served
  std::uint64_t in_reports = 0;    // box -> page
  std::uint64_t out_reports = 0;   // page -> box
  std::uint64_t out_dropped = 0;   // the box's queue was full
  std::uint64_t refused = 0;       // messages of the wrong size or type
  std::uint64_t features = 0;      // feature reports asked for (answered or refused by the box)
};

// Runs until the process is stopped; `ready` is called with the bound port once listening.
// Returns the exit code (2: cannot listen). Errors of one page's connection are one line on
// stderr each and never end the bridge.
int run_box_bridge(const BoxBridgeOptions& options, const std::function<void(std::uint16_t)>& ready);

}  // namespace cathbox::server
