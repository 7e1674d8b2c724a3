// The released coils' solve beside the attached tools' (Simulator::launch_released).
//
// Each step, the released coils on their turn (and awake) are solved on a thread of their own
// (BackgroundJob) while the calling thread solves the attached tools, each side from where the
// step began:
//  - the attached tools see the coils where their last solves left them, through the coils'
//    views (coil_views_): as they did when the coils were solved after them in the step;
//  - the coils see the attached tools where the step began, through the tools' views
//    (tool_views_) in a field of their own (released_contacts_), not where this step's solves
//    leave them: one step later than when they were solved after them.
// The sleep decides which coils are solved from its records up to the last step; a tool's move
// this step wakes a coil asleep on its next turn. The wall's per-node hints are kept apart per
// thread (ProbePoolScope). Solved on the calling thread instead (set_released_in_parallel(false)),
// the job runs at the same point from the same state: the results are the same, bit for bit.
// With released_overlap() the step returns before the job is over and the next one takes its
// results in first (finish_released at a fixed point either way: the same results again).
#include <memory>

#include "background_job.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {

Simulator::~Simulator() {
  if (job_) job_->finish();
}

void Simulator::settle() {
  if (pending_) finish_released();
}

void Simulator::set_released_overlap(bool on) {
  settle();
  overlap_ = on;
}
Simulator::Simulator(Simulator&&) noexcept = default;
Simulator& Simulator::operator=(Simulator&&) noexcept = default;

void Simulator::set_released_in_parallel(bool on) {
  settle();
  if (!job_) job_ = std::make_unique<BackgroundJob>();
  job_->set_threaded(on);
}

bool Simulator::released_in_parallel() const { return job_ ? job_->threaded() : BackgroundJob::threaded_by_default(); }

// A field member's rod as the job's field sees it: a released coil's view -> the coil, a tool ->
// its view, refreshed to the tool as the step begins when `refresh`.
const Rod* Simulator::job_rod(const Rod* rod, bool refresh) {
  for (std::size_t i = 0; i < coil_views_.size(); ++i) {
    if (rod == &coil_views_[i]) return &detached_[i];
  }
  for (std::size_t t = 0; t < rods_.size(); ++t) {
    if (rod != &rods_[t]) continue;
    if (refresh) tool_views_[t].mirror_contact_view(rods_[t]);
    return &tool_views_[t];
  }
  return rod;
}

void Simulator::launch_released(double dt_s) {
  if (!job_) job_ = std::make_unique<BackgroundJob>();
  // A wall that moved in place (the pulse) since the last step: every coil is solved again.
  if (wall_->revision() != wall_revision_) sleep_.wake_all();
  wall_revision_ = wall_->revision();
  update_contact_members();
  solving_.clear();
  for (std::size_t i = 0; i < detached_.size(); ++i) {
    if (!released_coil_turn(i)) continue;
    const bool was_asleep = sleep_.asleep(i);
    if (!sleep_.wake_before(i, detached_)) continue;
    if (was_asleep) detached_[i].forget_motion();
    solving_.push_back(i);
  }
  if (solving_.empty()) return;
  if (tool_views_.size() != rods_.size()) {
    tool_views_.clear();
    for (const Rod& rod : rods_) tool_views_.push_back(Rod::contact_view_of(rod));
    released_contacts_ = RodContactField(contacts_.margin_mm());
  }
  // The coils' field: the same members, the tools' views for the tools (frozen), the coils
  // themselves.
  released_members_.assign(members_.begin(), members_.end());
  for (RodContactField::Member& m : released_members_) {
    m.rod = job_rod(m.rod, true);
    m.frozen = !m.frozen;  // the tools' views are read, the coils solved
    if (m.hollow != nullptr) m.hollow = job_rod(m.hollow, false);  // compared, never read
  }
  released_dt_s_ = dt_s * static_cast<double>(released_turn_);
  job_->start(&Simulator::solve_released, this);
}

void Simulator::solve_released(void* simulator) {
  Simulator& sim = *static_cast<Simulator*>(simulator);
  const ProbePoolScope pool(1);
  // The field's members are set here, off the caller's thread: carrying its list over to moved
  // edge ranges (a node crossing a catheter's tip) walks every listed pair.
  sim.released_contacts_.set_members(sim.released_members_);
  for (const std::size_t i : sim.solving_) sim.detached_[i].step(sim.released_dt_s_, *sim.wall_, &sim.released_contacts_);
}

void Simulator::finish_released() {
  pending_ = false;
  released_timing_ = {};
  if (job_ && !solving_.empty()) {
    job_->finish();
    released_timing_ = {job_->last_run_us(), job_->last_wait_us()};
  }
  for (const std::size_t i : solving_) {
    coil_views_[i].mirror_published_view(detached_[i]);
    if (observer_ != nullptr) observer_->solved(true, i, detached_[i]);
  }
  for (std::size_t i = 0; i < detached_.size(); ++i) {
    if ((launched_step_ + i) % released_turn_ == 0) sleep_.coil_solved(i, detached_, contacts_.margin_mm(), static_cast<int>(released_turn_));
  }
}

}  // namespace cathbox::tool
