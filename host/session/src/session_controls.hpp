#pragma once
// The session's own control handlers (Session's private nested classes, session_controls.cpp):
// the tool the hand holds, the coil's detachment and the next coil, the balloon's inflation
// device; and the sink the hand's controls go through.
#include "session/session.hpp"

namespace cathbox::session {

// Controls the hand issues go straight to the session's apply().
class Session::Sink final : public ControlSink {
 public:
  explicit Sink(Session& s) : s_(s) {}
  void push(const Control& control) override { s_.apply(control); }

 private:
  Session& s_;
};

// kSelectTool: the hand takes another tool (payload: its index, or 0xFF for the next one).
class Session::SelectTool final : public ControlHandler {
 public:
  explicit SelectTool(Session& s) : s_(s) {}
  bool apply(Control& c, ControlContext& ctx) override;

 private:
  Session& s_;
};

// kDetachCoil: release a coil tool's coil (payload: the tool's index). Refused (not applied,
// not recorded) while the detachment zone is still in the catheter.
class Session::DetachCoil final : public ControlHandler {
 public:
  explicit DetachCoil(Session& s) : s_(s) {}
  bool apply(Control& c, ControlContext& ctx) override;

 private:
  Session& s_;
};

// kLoadCoil: the coil tool's old pusher withdrawn, its next coil fed at the hub (payload: the
// tool's index). Refused (not applied, not recorded) before its coil is detached or when the
// case lists no further coil.
class Session::LoadCoil final : public ControlHandler {
 public:
  explicit LoadCoil(Session& s) : s_(s) {}
  bool apply(Control& c, ControlContext& ctx) override;

 private:
  Session& s_;
};

// kBalloon: the inflation device of a balloon tool (payload: tool, BalloonOp, f64 value). A
// value the balloon does not take is refused (not applied, not recorded) with a log line.
class Session::BalloonControl final : public ControlHandler {
 public:
  explicit BalloonControl(Session& s) : s_(s) {}
  bool apply(Control& c, ControlContext& ctx) override;

 private:
  Session& s_;
};

}  // namespace cathbox::session
