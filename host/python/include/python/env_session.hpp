#pragma once
// One session driven by a program, as the Python module's environments drive it: a case loaded
// the one way every front end loads it (session::load_session_case), a session::Session in
// virtual time whose hand is a session::ProgramHand (every tool at the speeds the program sets,
// mm/s and rad/s), optionally recorded to a .cbxrec, and the state after each call of step()
// (tools' nodes, tips, contacts, hand forces, metrics, the state hash) readable between calls.
//
//   auto s = python::EnvSession::open("cases/y_bifurcation.case", {});
//   s.value()->set_speed(0, 10.0, 0.0);      // the guidewire in at 10 mm/s
//   s.value()->step(133);                    // 133 ticks of 1 ms, on this thread
//   s.value()->state().tools[0].positions_mm ...
//
// Clone: a Session cannot be copied (its simulator holds a collision tree, rods, a recorder),
// so clone() rebuilds the case from the bytes the session keeps (its record header: the case
// and vessel files as they were opened, whatever the files hold now) and feeds the new session every (speeds, ticks) this one was
// given; the record design makes that exact (same inputs, same states: the state hashes are
// compared, and a clone whose hash differs is an error). Its cost grows with the episode.
//
// One thread at a time per EnvSession; different EnvSessions share nothing and may step on
// different threads at once.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "base/result.hpp"
#include "flow/c_arm.hpp"
#include "session/program_hand.hpp"
#include "session/session.hpp"
#include "tool/snapshot.hpp"

namespace cathbox::python {

struct EnvSessionOptions {
  std::int64_t period_us = 1000;  // the tick
  bool end_at_target = true;      // the run ends when the held tool's tip reaches the target
  std::string record_path;        // a .cbxrec to write (empty: none)
  std::string who = "python";     // the program: the record's hand description
};

class EnvSession {
 public:
  // The case (a .case file or a bare .hclm); errors are one line naming the file.
  [[nodiscard]] static base::Result<std::unique_ptr<EnvSession>> open(const std::string& case_path,
                                                                      const EnvSessionOptions& options);
  ~EnvSession();
  EnvSession(const EnvSession&) = delete;
  EnvSession& operator=(const EnvSession&) = delete;

  [[nodiscard]] std::size_t tool_count() const { return session_->tool_names().size(); }
  // From the next tick. Errors (nothing changed): a tool index out of range, a speed that is not
  // finite.
  [[nodiscard]] base::Status<> set_speed(std::size_t tool, double insertion_mm_s, double rotation_rad_s);
  // Runs up to `ticks` ticks (fewer when the run ends); returns how many ran.
  std::int64_t step(std::int64_t ticks);
  // A second session in the same state (see above); not recorded.
  [[nodiscard]] base::Result<std::unique_ptr<EnvSession>> clone() const;
  // Ends the run and closes the record (idempotent). Error: the record could not be finished.
  [[nodiscard]] base::Status<> close();

  // The state after the last step (before the first: the case's initial state). The vectors
  // stay where they are until the next step() (a node count that grows may move them then).
  [[nodiscard]] const tool::Snapshot& state() const { return snap_; }
  [[nodiscard]] const session::Metrics& metrics() const { return session_->metrics(); }
  [[nodiscard]] const session::Session& session() const { return *session_; }
  [[nodiscard]] session::Session& session() { return *session_; }
  // Holds the fluoroscopy foot pedal down from the next tick: the session's fluoroscopy unit
  // pulses (its images are the trainer's; host/app's OffscreenFluoro draws them). Recorded, and
  // replayed by clone().
  void press_pedal();
  [[nodiscard]] const session::SessionCase& scene() const { return session_->scene(); }
  [[nodiscard]] bool over() const { return session_->over(); }
  [[nodiscard]] std::int64_t ticks() const { return session_->ticks(); }
  [[nodiscard]] std::uint64_t state_hash() const;
  // Ticks on which some solved tool's solve did not converge (its contact reading was held); a
  // tool all inside its outer tool is not solved and does not count.
  [[nodiscard]] std::int64_t unconverged_ticks() const { return unconverged_ticks_; }
  // The largest wall force of the last tick, from converged steps (session/contact_readings.hpp).
  [[nodiscard]] double wall_force_mN() const { return wall_force_mN_; }

  // The C-arm the tracked points and images are projected through (default: AP, its isocentre
  // halfway between the entry and the target). Error: a pose out of range.
  [[nodiscard]] base::Status<> set_c_arm(const flow::CArmPose& pose);
  [[nodiscard]] const flow::CArm& c_arm() const { return c_arm_; }

 private:
  struct Input {
    std::array<session::ToolSpeed, session::kMaxTools> speeds{};
    std::int64_t ticks = 0;
  };
  class Readings;
  explicit EnvSession(EnvSessionOptions options);
  [[nodiscard]] static base::Result<std::unique_ptr<EnvSession>> start(session::SessionCaseLoad loaded,
                                                                       const EnvSessionOptions& options);

  EnvSessionOptions options_;
  session::ProgramHand* hand_ = nullptr;  // owned by session_
  std::unique_ptr<Readings> readings_;     // the session's observer: declared first, destroyed last
  std::unique_ptr<session::Session> session_;
  tool::Snapshot snap_;
  std::vector<Input> inputs_;  // every step's speeds and ticks (clone)
  std::vector<std::size_t> pedal_at_;  // the pedal was pressed before inputs_[i] (clone)
  std::vector<const glm::dvec3*> rod_buffers_;  // each tool's rod positions: fixed for the session's life
  std::int64_t unconverged_ticks_ = 0;
  double wall_force_mN_ = 0.0;
  flow::CArm c_arm_;
  bool closed_ = false;
};

}  // namespace cathbox::python
