// Sleeping released coils (coil_sleep.hpp).
#include "tool/coil_sleep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::tool {

namespace {
constexpr std::size_t kChunkNodes = 8;

// Node k's own reach: its radius and half its longer edge (a point of an edge near it).
double node_reach(const Rod& rod, std::size_t k) {
  const std::span<const glm::dvec3> x = rod.positions();
  double edge = 0.0;
  if (k > 0) edge = std::max(edge, glm::length(x[k] - x[k - 1]));
  if (k + 1 < x.size()) edge = std::max(edge, glm::length(x[k + 1] - x[k]));
  return rod.node_radius_mm(k) + 0.5 * edge;
}
}  // namespace

std::size_t CoilSleep::asleep_count() const {
  return static_cast<std::size_t>(std::count_if(coils_.begin(), coils_.end(), [](const Coil& c) { return c.asleep; }));
}

void CoilSleep::wake_all() {
  for (Coil& c : coils_) {
    if (c.asleep) ++wakes_;
    c = Coil{};
  }
  chunks_.clear();
}

bool CoilSleep::near(const Coil& c, const Rod& coil, const glm::dvec3& p, double r, double margin_mm) const {
  const double pad = r + margin_mm + settings_.skin_mm;
  for (int a = 0; a < 3; ++a) {
    if (p[a] < c.lo[a] - pad || p[a] > c.hi[a] + pad) return false;
  }
  const std::span<const glm::dvec3> x = coil.positions();
  for (std::size_t h = c.chunk_first; h < c.chunk_first + c.chunk_count; ++h) {
    const Chunk& ch = chunks_[h];
    if (glm::length(p - ch.centre) > ch.reach + pad) continue;
    for (std::size_t k = ch.first; k < ch.last; ++k) {
      if (glm::length(p - x[k]) <= node_reach(coil, k) + pad) return true;
    }
  }
  return false;
}

// The moves of a rod's nodes in its solve, recorded against every sleeping coil they are near;
// `last` becomes the rod's positions. Returns the largest move. A rod whose node count changed
// (new, cut at a detachment, reloaded) moved by an unknown amount: infinite, for every sleeping
// coil any of its nodes is near.
double CoilSleep::disturb(const Rod& rod, std::vector<glm::dvec3>& last, std::span<const Rod> coils, double margin_mm) {
  const std::span<const glm::dvec3> x = rod.positions();
  const bool known = last.size() == x.size();
  constexpr double kUnknown = std::numeric_limits<double>::infinity();
  // Moves compared as squares and rooted only where a sleeping coil is to be told (the root is
  // monotonic: the root of the largest square is the largest root, the same bits; glm::length is
  // the root of the dot product). With no other coil asleep that is once, for the largest.
  bool any_asleep = false;
  for (std::size_t s = 0; s < coils_.size(); ++s) any_asleep = any_asleep || (coils_[s].asleep && &coils[s] != &rod);
  double worst_sq = known ? 0.0 : kUnknown;
  for (std::size_t k = rod.first_node(); k < x.size(); ++k) {
    const glm::dvec3 d = known ? x[k] - last[k] : glm::dvec3(0.0);
    const double m_sq = known ? glm::dot(d, d) : kUnknown;
    worst_sq = std::max(worst_sq, m_sq);
    if (!any_asleep || !(m_sq > 0.0)) continue;
    const double m = std::sqrt(m_sq);
    for (std::size_t s = 0; s < coils_.size(); ++s) {
      Coil& c = coils_[s];
      if (!c.asleep || &coils[s] == &rod || c.disturbed > settings_.wake_move_mm) continue;
      if (near(c, coils[s], x[k], rod.node_radius_mm(k), margin_mm)) c.disturbed += m;
    }
  }
  last.assign(x.begin(), x.end());
  return std::sqrt(worst_sq);
}

void CoilSleep::fall_asleep(std::size_t i, const Rod& coil) {
  Coil& c = coils_[i];
  c.asleep = true;
  c.disturbed = 0.0;
  c.still = 0;
  const std::span<const glm::dvec3> x = coil.positions();
  c.lo = glm::dvec3(std::numeric_limits<double>::infinity());
  c.hi = -c.lo;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double r = node_reach(coil, k);
    c.lo = glm::min(c.lo, x[k] - glm::dvec3(r));
    c.hi = glm::max(c.hi, x[k] + glm::dvec3(r));
  }
}

// The bounding spheres of every sleeping coil's runs of nodes (after a coil fell asleep or woke).
void CoilSleep::rebuild_chunks(std::span<const Rod> coils) {
  chunks_.clear();
  for (std::size_t i = 0; i < coils_.size(); ++i) {
    Coil& c = coils_[i];
    c.chunk_first = chunks_.size();
    c.chunk_count = 0;
    if (!c.asleep) continue;
    const std::span<const glm::dvec3> x = coils[i].positions();
    for (std::size_t first = 0; first < x.size(); first += kChunkNodes) {
      Chunk ch;
      ch.first = first;
      ch.last = std::min(x.size(), first + kChunkNodes);
      for (std::size_t k = ch.first; k < ch.last; ++k) ch.centre += x[k];
      ch.centre /= static_cast<double>(ch.last - ch.first);
      for (std::size_t k = ch.first; k < ch.last; ++k) {
        ch.reach = std::max(ch.reach, glm::length(x[k] - ch.centre) + node_reach(coils[i], k));
      }
      chunks_.push_back(ch);
      ++c.chunk_count;
    }
  }
}

// Coil i's solve, covering `ticks` steps (its turn), moved its nodes by at most `move`: at rest
// this solve (under rest_share of its tolerance), and for rest_ticks steps with no net drift over
// drift_share of it?
bool CoilSleep::at_rest(std::size_t i, const Rod& coil, double move, int ticks) {
  Coil& c = coils_[i];
  const std::span<const glm::dvec3> x = coil.positions();
  const double tolerance = coil.settings().convergence_mm;
  if (!(move <= settings_.rest_share * tolerance)) {
    c.still = 0;
    return false;
  }
  std::vector<glm::dvec3>& from = window_[i];
  double drift = 0.0;
  for (std::size_t k = 0; c.still > 0 && k < x.size(); ++k) drift = std::max(drift, glm::length(x[k] - from[k]));
  if (c.still == 0 || from.size() != x.size() || !(drift <= settings_.drift_share * tolerance)) {
    from.assign(x.begin(), x.end());  // a new window from here
    c.still = ticks;
    return c.still >= settings_.rest_ticks;
  }
  c.still += ticks;
  return c.still >= settings_.rest_ticks;
}

void CoilSleep::begin(std::span<const Rod> tools, std::span<const Rod> coils) {
  if (!settings_.enabled) {
    if (asleep_count() > 0) wake_all();
    return;
  }
  if (coils_.size() != coils.size()) {
    coils_.resize(coils.size());
    coil_last_.resize(coils.size());
    window_.resize(coils.size());
    std::size_t most = 0;
    for (const Rod& c : coils) most += (c.node_total() + kChunkNodes - 1) / kChunkNodes;
    chunks_.reserve(most);
    rebuild_chunks(coils);
  }
  tool_last_.resize(tools.size());
}

void CoilSleep::tool_solved(std::size_t t, std::span<const Rod> tools, std::span<const Rod> coils, double margin_mm) {
  if (settings_.enabled && t < tool_last_.size()) disturb(tools[t], tool_last_[t], coils, margin_mm);
}

bool CoilSleep::wake_before(std::size_t i, std::span<const Rod> coils) {
  if (!settings_.enabled || i >= coils_.size()) return true;
  Coil& c = coils_[i];
  if (!c.asleep) return true;
  if (!(c.disturbed > settings_.wake_move_mm)) return false;
  c = Coil{};
  ++wakes_;
  rebuild_chunks(coils);
  return true;
}

void CoilSleep::coil_solved(std::size_t i, std::span<const Rod> coils, double margin_mm, int ticks) {
  if (!settings_.enabled || i >= coils_.size()) return;
  if (coils_[i].asleep) {
    ++skipped_;
    return;
  }
  const double move = disturb(coils[i], coil_last_[i], coils, margin_mm);
  if (at_rest(i, coils[i], move, ticks)) {
    fall_asleep(i, coils[i]);
    rebuild_chunks(coils);
  }
}

}  // namespace cathbox::tool
