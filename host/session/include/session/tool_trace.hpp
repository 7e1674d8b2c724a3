#pragma once
// Every tool's state tick by tick over a window of a run, for tracing a jump in the hand force to
// its cause: the force and its change, the rod's own part, the clamp, the solve (converged,
// Newton iterations), the tip and its carrier's steering push, and every wall contact of the free
// part (each node's force, normal and friction) and rod-rod contact. `cathbox session replay REC
// --trace FROM-TO` prints it for a record (host/cli/README.md has the columns).
#include <cstdint>
#include <cstdio>
#include <vector>

#include "session/session.hpp"

namespace cathbox::session {

class ToolTrace final : public TickObserver {
 public:
  // Ticks whose time is within [from_us, to_us], a line per tool, written to `out`.
  ToolTrace(std::int64_t from_us, std::int64_t to_us, std::FILE* out) : from_us_(from_us), to_us_(to_us), out_(out) {}
  void observe(const TickView& v) override;
  [[nodiscard]] std::int64_t lines() const { return lines_; }

 private:
  std::int64_t from_us_, to_us_;
  std::FILE* out_;
  std::vector<double> last_mN_;  // each tool's hand force at the tick before
  std::int64_t lines_ = 0;
};

}  // namespace cathbox::session
