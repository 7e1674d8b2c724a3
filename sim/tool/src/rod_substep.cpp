// A tick whose Newton solve ends unconverged is solved again from its start, as 2, then 4 (up
// to RodSettings::substeps_max) equal sub-increments of the motion imposed at the clamp (the
// insertion and the rotation; an inner tool's material advance all in the first), each of dt / parts: the
// tool's velocity, hence its drag and the hand's rate terms, stays the tick's, while each solve
// starts 1 / parts as far from its equilibrium and the solver's drag floor holds each node
// parts times stiffer. A fixed, deterministic count: never a time budget (replays stay
// bit-identical on every target). The tick's state and hand force are its last sub-step's.
// The entry's move with a carrier's tip (move_entry, before the step) is not subdivided.
#include <algorithm>
#include <cmath>

#include "rod_node_contact.hpp"
#include "rod_step_start.hpp"

namespace cathbox::tool {

namespace {

template <typename T>
void keep(std::vector<T>& into, const std::vector<T>& from, std::size_t first) {
  into.assign(from.begin() + static_cast<std::ptrdiff_t>(std::min(first, from.size())), from.end());
}

template <typename T>
void put_back(std::vector<T>& into, const std::vector<T>& from, std::size_t first) {
  std::copy(from.begin(), from.end(), into.begin() + static_cast<std::ptrdiff_t>(first));
}

}  // namespace

void Rod::step(double dt_s, const WallModel& wall, const RodObstacles* obstacles) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) dt_s = 1e-3;
  const int most = settings_.substeps_max;
  if (most > 1) save_step_start();
  const double insertion = insertion_mm_;
  const double rotation = rotation_rad_;
  const double advance = material_advance_mm_;
  step_once(dt_s, wall, obstacles);
  last_substeps_ = 1;
  for (int parts = 2; parts <= most && !warm_ok_ && first_free_ < x_.size(); parts *= 2) {
    restore_step_start(parts);
    const double insertion0 = stepped_insertion_mm_;
    const double rotation0 = stepped_rotation_rad_;
    for (int j = 1; j <= parts; ++j) {
      const double u = static_cast<double>(j) / parts;
      insertion_mm_ = j == parts ? insertion : insertion0 + (insertion - insertion0) * u;
      rotation_rad_ = j == parts ? rotation : rotation0 + (rotation - rotation0) * u;
      // A carried tool's material advance (its slide along its carrier's path, one follow-the-
      // leader move in advect) goes whole into the first part: cut into parts it folded the
      // steered wire of NestedTools.MicrocatheterFollowsTheWireWhereverItWasSteered in 20 of 20
      // placements (convergence.md, "Every tool sub-stepped, the advance whole in the first part").
      // A lone tool has none set (NaN: each part advances by its own insertion change).
      material_advance_mm_ = std::isfinite(advance) ? (j == 1 ? advance : 0.0) : advance;
      step_once(dt_s / parts, wall, obstacles);
      stepped_rotation_rad_ = rotation_rad_;
    }
    last_substeps_ = parts;
  }
  stepped_rotation_rad_ = rotation_rad_;
}

void Rod::save_step_start() {
  if (!step_start_) step_start_ = std::make_unique<StepStart>();
  StepStart& s = *step_start_;
  s.from = first_;
  s.pair_with(
      *this, [&](auto& kept, const auto& live) { keep(kept, live, first_); },
      [](auto& kept, const auto& live) { kept = live; });
}

// Back to the step's start; the last converged motion the warm start reads is cut to a part's.
void Rod::restore_step_start(int parts) {
  StepStart& s = *step_start_;
  const std::size_t from = s.from;
  // Nodes that joined the window below its start during the failed attempt go back outside.
  for (std::size_t k = std::min(first_, from); k < from; ++k) place_outside(k);
  // The wall hints stay the ones the failed attempt left: a node whose first probe in its
  // thread's pool took a slot there (a released coil's first solve after its release, in probe
  // pool 1) keeps it, warm, instead of taking another, cold, on every try in parts (a hint only
  // speeds a query up: the results are the same).
  for (std::size_t k = from; k < node_contacts_.size() && k - from < s.node_contacts.size(); ++k) {
    s.node_contacts[k - from].hint = node_contacts_[k].hint;
    s.node_contacts[k - from].edge.hint = node_contacts_[k].edge.hint;
  }
  s.pair_with(
      *this, [&](const auto& kept, auto& live) { put_back(live, kept, from); },
      [](const auto& kept, auto& live) { live = kept; });
  const double scale = 1.0 / parts;
  for (std::size_t k = warm_first_; k < solved_move_.size(); ++k) solved_move_[k] *= scale;
}

}  // namespace cathbox::tool
