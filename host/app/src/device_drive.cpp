#include "app/device_drive.hpp"

#include <cstdio>

namespace cathbox::app {
namespace {

// "12 / 20 mm" of the stent out.
std::string out_of(const session::ToolView& stent) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.0f / %.0f mm", static_cast<double>(stent.stent_unsheathed_mm), static_cast<double>(stent.stent_length_mm));
  return buf;
}

// "5 mm/s": a drive's speed as the HUD names it (from the constants the drive moves at).
std::string speed(double mm_s) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%.0f mm/s", mm_s);
  return buf;
}

bool fully_out(const session::ToolView& stent) {
  return stent.stent_unsheathed_mm >= stent.stent_length_mm - DeviceDrive::kFullyOut_mm;
}

}  // namespace

int DeviceDrive::stent_tool(const session::SceneSnapshot& snap) {
  for (int i = 0; i < snap.tool_count; ++i) {
    const session::ToolView& t = snap.tools[static_cast<std::size_t>(i)];
    if (t.stent_length_mm > 0.0F && t.stent_carrier >= 0 && t.stent_carrier < snap.tool_count) return i;
  }
  return -1;
}

DriveCommand DeviceDrive::update(const DriveKeys& keys, const session::SceneSnapshot& snap) {
  box_ = keys.box;
  if (mode_ != Mode::kIdle && snap.run_over) return stop("the run is over: the drive stops");
  if (keys.box) return box_holds(keys);
  if (keys.cancel) return mode_ != Mode::kIdle ? stop(mode_ == Mode::kUnsheathe ? "U: unsheathing stopped" : "E: retrieval stopped") : DriveCommand{};
  if (keys.unsheathe) return mode_ == Mode::kUnsheathe ? stop("U: unsheathing stopped") : start(Mode::kUnsheathe, snap);
  if (keys.retrieve) return mode_ == Mode::kRetrieve ? stop("E: retrieval stopped") : start(Mode::kRetrieve, snap);
  return mode_ != Mode::kIdle ? drive(snap) : DriveCommand{};
}

// A box holds the hand: the keys refused, a drive running stopped.
DriveCommand DeviceDrive::box_holds(const DriveKeys& keys) {
  if (keys.unsheathe) return stop("U: refused while a box drives the tools (draw the catheter back on the box)");
  if (keys.retrieve) return stop("E: refused while a box drives the tools (pull the stent back on the box)");
  return mode_ != Mode::kIdle ? stop("a box drives the tools: the drive stops") : DriveCommand{};
}

DriveCommand DeviceDrive::start(Mode mode, const session::SceneSnapshot& snap) {
  const char* key = mode == Mode::kUnsheathe ? "U" : "E";
  const int stent = stent_tool(snap);
  mode_ = Mode::kIdle;
  if (stent < 0) return {false, 0.0, std::nullopt, std::string(key) + ": no stent retriever in a catheter in this case"};
  const session::ToolView& st = snap.tools[static_cast<std::size_t>(stent)];
  if (mode == Mode::kUnsheathe && fully_out(st)) return {false, 0.0, std::nullopt, "U: the stent is already unsheathed"};
  if (mode == Mode::kRetrieve && st.stent_unsheathed_mm <= 0.0F) return {false, 0.0, std::nullopt, "E: the stent is not unsheathed"};
  mode_ = mode;
  tool_ = mode == Mode::kUnsheathe ? static_cast<std::size_t>(st.stent_carrier) : static_cast<std::size_t>(stent);
  pass_seen_ = false;
  DriveCommand c = drive(snap);
  if (c.driving && snap.held_tool != tool_) c.select = tool_;
  return c;
}

DriveCommand DeviceDrive::drive(const session::SceneSnapshot& snap) {
  const int stent = stent_tool(snap);
  if (stent < 0) return stop("the stent retriever is gone: the drive stops");
  const session::ToolView& st = snap.tools[static_cast<std::size_t>(stent)];
  double speed_mm_s = 0.0;
  if (mode_ == Mode::kUnsheathe) {
    if (fully_out(st)) return stop("U: the stent is unsheathed (" + out_of(st) + ")");
    speed_mm_s = -kUnsheathe_mm_s;
  } else {
    pass_seen_ = pass_seen_ || st.stent_retrieving;
    if (st.stent_unsheathed_mm <= 0.0F || (pass_seen_ && !st.stent_retrieving)) {
      return stop(pass_seen_ ? "E: the stent is back in a catheter: the pass has ended" : "E: the stent is back in a catheter");
    }
    speed_mm_s = -kRetrieve_mm_s;
  }
  if (snap.held_tool != tool_) return {true, 0.0, std::nullopt, {}};  // the select is not applied yet
  if (snap.insertion_mm <= 0.0) return stop("the driven tool is out to its hub: the drive stops");
  return {true, speed_mm_s, std::nullopt, {}};
}

DriveCommand DeviceDrive::stop(std::string note) {
  mode_ = Mode::kIdle;
  return {false, 0.0, std::nullopt, std::move(note)};
}

std::vector<std::string> DeviceDrive::hints(const session::SceneSnapshot& snap, const std::vector<std::string>& names) const {
  const int stent = stent_tool(snap);
  if (stent < 0) return {};
  const session::ToolView& st = snap.tools[static_cast<std::size_t>(stent)];
  const auto carrier = static_cast<std::size_t>(st.stent_carrier);
  const std::string carrier_name = carrier < names.size() ? names[carrier] : std::string("catheter");
  if (box_) return {"U, E: off while a box drives the tools (" + out_of(st) + " of the stent out)"};
  std::vector<std::string> out;
  if (mode_ == Mode::kUnsheathe) {
    out.push_back("U: UNSHEATHING " + out_of(st) + ", the " + carrier_name + " back at " + speed(kUnsheathe_mm_s) + " (U, arrows or Tab: stop)");
  } else {
    out.push_back(fully_out(st) ? "U: the stent is unsheathed (" + out_of(st) + ")"
                                : "U: unsheathe the stent (" + out_of(st) + " out; the " + carrier_name + " back at " + speed(kUnsheathe_mm_s) + ")");
  }
  if (mode_ == Mode::kRetrieve) {
    out.push_back("E: RETRIEVING at " + speed(kRetrieve_mm_s) + (st.stent_retrieving ? ", pass running" : "") +
                  " (E, arrows or Tab: stop)");
  } else if (st.stent_unsheathed_mm > 0.0F) {
    out.push_back("E: retrieve the stent (back at " + speed(kRetrieve_mm_s) + " into a catheter)");
  }
  return out;
}

}  // namespace cathbox::app
