// The predictor: before each solve the free nodes follow the present centreline by the
// insertion change (follow the leader), the part near the entry follows the entry's move (an
// inner tool riding on its carrier's tip), and a compressed straight or flat rod gets the lateral
// imperfection that lets it buckle. The elastic solve then corrects the shape.
#include <algorithm>
#include <cmath>
#include <span>

#include <glm/geometric.hpp>

#include "base/portable_math.hpp"
#include "rod_geometry.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {

using rod_detail::perpendicular_unit;

namespace {

// A point on the chord from b to c (inside the circle through a, b and c; a on either side of
// b) moved out along the circle's radius onto it; false when the three are (nearly) in line.
// The chord's point a fraction u along turns to the circle's point about a fraction u of the
// arc along (the difference is of the order of the arc angle cubed): moving every node of a
// circular polygon this way turns it rigidly, its edge lengths and turning angles kept.
bool onto_arc(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& chord, glm::dvec3& out) {
  const glm::dvec3 p = a - b;
  const glm::dvec3 q = c - b;
  const glm::dvec3 w = glm::cross(p, q);
  const double w2 = glm::dot(w, w);
  if (!(w2 > 1e-12 * glm::dot(p, p) * glm::dot(q, q))) return false;
  const glm::dvec3 centre = b + glm::cross(glm::dot(p, p) * q - glm::dot(q, q) * p, w) / (2.0 * w2);
  const glm::dvec3 r = chord - centre;
  const double len = glm::length(r);
  if (!(len > 0.0)) return false;
  out = centre + r * (glm::length(b - centre) / len);
  return true;
}

// How far the nodes from `first` on lie out of the plane through the line (entry, dir) that
// holds the node farthest from it (0 for a straight rod, or one bent in that plane only).
double out_of_plane_mm(std::span<const glm::dvec3> x, std::size_t first, const glm::dvec3& entry, const glm::dvec3& dir) {
  glm::dvec3 farthest(0.0);
  double far2 = 0.0;
  for (std::size_t k = first; k < x.size(); ++k) {
    const glm::dvec3 r = x[k] - entry;
    const glm::dvec3 side = r - dir * glm::dot(r, dir);
    const double d2 = glm::dot(side, side);
    if (d2 > far2) {
      far2 = d2;
      farthest = side;
    }
  }
  if (!(far2 > 0.0)) return 0.0;
  const glm::dvec3 normal = glm::cross(dir, farthest / std::sqrt(far2));
  double out = 0.0;
  for (std::size_t k = first; k < x.size(); ++k) out = std::max(out, std::abs(glm::dot(x[k] - entry, normal)));
  return out;
}

// The fewest free nodes a compressed rod is seeded with. The out-of-plane test reads 0 for one
// free node whatever its place (a plane through the entry line holds any one point), and for two
// reads under the seed while the short rod is near straight (a straight one from the entry lies
// in one such plane; the stent case's two-node rods read ~0.1 um), which one this short is: far
// under its buckling load (clamped-free Euler pi^2 EI / (4 l^2), l <= two edges), it has nothing
// to buckle into, so seeding it on every compressed step only shakes it.
constexpr std::size_t kSeedNodesMin = 3;

}  // namespace

void Rod::advect(double delta_mm) {
  // Predictor: every free node slides along the present centreline by the insertion change
  // (follow the leader); the elastic solve then corrects the shape. Beyond the tip the path
  // continues straight; proximal of the window it is the entry line.
  const std::size_t n = x_.size();
  if (delta_mm == 0.0) return;
  const double old_insertion = insertion_mm_ - delta_mm;
  const std::size_t new_kp = rod_detail::last_outside(from_tip_, insertion_mm_, stepped_insertion_mm_);
  std::size_t j = first_;  // segment [j, j+1] of the old curve holding the target station
  for (std::size_t k = new_kp + 1; k < n; ++k) {
    const double s = from_tip_[k] - delta_mm;  // station (old curve) the node moves to
    if (s >= from_tip_[first_]) {
      x_pred_[k] = entry_ + dir_ * (old_insertion - s);
    } else if (s <= 0.0) {
      // Ahead of the tip: along the leader (a wire beyond this catheter) or straight on.
      const double leader_station = leader_ != nullptr ? leader_insertion_mm_ - (old_insertion - s) : -1.0;
      if (leader_ != nullptr && leader_station >= 0.0) {
        x_pred_[k] = leader_->point_at_from_tip(leader_station);
      } else {
        x_pred_[k] = x_[n - 1] + t_[n - 2] * (-s);
      }
    } else {
      while (j + 2 < n && from_tip_[j + 1] > s) ++j;
      while (j > first_ && from_tip_[j] < s) --j;
      const double u = std::clamp((from_tip_[j] - s) / rest_[j], 0.0, 1.0);
      x_pred_[k] = x_[j] + (x_[j + 1] - x_[j]) * u;
      // A coil's loops: along the circles through the neighbours instead of the chord (the
      // mean of the circles before and after the edge), so the slide keeps edge lengths.
      glm::dvec3 before, after;
      const glm::dvec3 chord = x_pred_[k];
      const bool has_before = settings_.arc_predictor && j > first_ && onto_arc(x_[j - 1], x_[j], x_[j + 1], chord, before);
      const bool has_after = settings_.arc_predictor && j + 2 < n && onto_arc(x_[j + 2], x_[j + 1], x_[j], chord, after);
      if (has_before && has_after) x_pred_[k] = 0.5 * (before + after);
      else if (has_before) x_pred_[k] = before;
      else if (has_after) x_pred_[k] = after;
    }
  }
  for (std::size_t k = new_kp + 1; k < n; ++k) x_[k] = x_pred_[k];
}

void Rod::move_entry(const glm::dvec3& point_mm, const glm::dvec3& direction, const glm::dvec3& reference) {
  const double len = glm::length(direction);
  if (!(len > 1e-12) || !std::isfinite(len) || !std::isfinite(point_mm.x + point_mm.y + point_mm.z)) return;
  // Predictor: the free part near the entry follows the entry's move (the carrier's tip), fading
  // out over kFollowEntry_mm along the tool, so the clamp does not tear at the first nodes.
  const glm::dvec3 moved = point_mm - entry_;
  if (glm::dot(moved, moved) > 0.0 && first_free_ < x_.size()) {
    constexpr double kFollowEntry_mm = 10.0;
    const double s0 = from_tip_[first_free_ - 1];
    for (std::size_t k = first_free_; k < x_.size(); ++k) {
      const double w = 1.0 - (s0 - from_tip_[k]) / kFollowEntry_mm;
      if (w <= 0.0) break;
      x_[k] += moved * w;
    }
  }
  entry_ = point_mm;
  dir_ = direction / len;
  const glm::dvec3 r = reference - dir_ * glm::dot(reference, dir_);
  const double rl = glm::length(r);
  entry_d1_ = rl > 1e-9 ? r / rl : perpendicular_unit(dir_);
}

bool Rod::seed_buckling() {
  // A perfectly straight rod pushed along its axis stays on the unstable straight branch, and
  // one bent in a single plane (a pre-curved tip in a straight tube) in that plane: the solve
  // has nothing across it to grow, so the wire buckles flat where a real one goes helical
  // (docs/sim-tool/convergence.md, "What the hand-force replays check"). Real tools are never
  // perfectly straight nor perfectly flat, so give the free nodes a tiny lateral offset. A rod
  // already out of every plane through its entry line by more than the offset would give (by
  // the vessel's path, its own shape or an earlier seed) needs none: seeding it again every
  // compressed step only shakes it (and the shaken rod then spends Newton iterations taking the
  // offset back out). A rod of fewer than kSeedNodesMin free nodes is never seeded. Whether it
  // seeded: a step seeded starts cold (start_solve); one too short to seed keeps its warm start.
  const std::size_t n = x_.size();
  if (n - first_free_ < kSeedNodesMin) return false;
  if (out_of_plane_mm(x_, first_free_, entry_, dir_) > settings_.buckling_seed_mm) return false;
  for (std::size_t k = first_free_; k < n; ++k) {
    const std::size_t e = std::min(k, n - 2);
    const double a = 0.7 * static_cast<double>(k);
    x_[k] += (m1_[e] * base::portable::cos(a) + m2_[e] * base::portable::sin(a)) * settings_.buckling_seed_mm;
  }
  return true;
}

}  // namespace cathbox::tool
