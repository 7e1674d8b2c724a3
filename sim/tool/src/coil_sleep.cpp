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

// The moves of a solved rod's nodes this step, recorded against every sleeping coil they are
// near; `last` becomes the rod's positions. Returns the largest move (infinite for a new rod).
double CoilSleep::disturb(const Rod& rod, std::vector<glm::dvec3>& last, std::span<const Rod> coils, double margin_mm) {
  const std::span<const glm::dvec3> x = rod.positions();
  double worst = std::numeric_limits<double>::infinity();
  if (last.size() == x.size()) {
    worst = 0.0;
    for (std::size_t k = rod.first_node(); k < x.size(); ++k) {
      const double m = glm::length(x[k] - last[k]);
      worst = std::max(worst, m);
      if (!(m > 0.0)) continue;
      for (std::size_t s = 0; s < coils_.size(); ++s) {
        if (!coils_[s].asleep || &coils[s] == &rod || m <= step_disturb_[s]) continue;
        if (near(coils_[s], coils[s], x[k], rod.node_radius_mm(k), margin_mm)) step_disturb_[s] = m;
      }
    }
  }
  last.assign(x.begin(), x.end());
  return worst;
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

// The bounding spheres of every sleeping coil's runs of nodes (after a coil fell asleep).
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

void CoilSleep::observe(std::span<const Rod> tools, std::span<const Rod> coils, double margin_mm) {
  if (!settings_.enabled) {
    if (asleep_count() > 0) wake_all();
    return;
  }
  skipped_ += asleep_count();  // the coils asleep now were not solved in this step
  if (coils_.size() != coils.size()) {
    coils_.resize(coils.size());
    coil_last_.resize(coils.size());
    rebuild_chunks(coils);
  }
  tool_last_.resize(tools.size());
  step_disturb_.assign(coils.size(), 0.0);
  for (std::size_t t = 0; t < tools.size(); ++t) disturb(tools[t], tool_last_[t], coils, margin_mm);
  bool changed = false;
  for (std::size_t i = 0; i < coils.size(); ++i) {
    Coil& c = coils_[i];
    if (c.asleep) continue;
    const double move = disturb(coils[i], coil_last_[i], coils, margin_mm);
    c.still = move <= settings_.rest_move_mm ? c.still + 1 : 0;
    if (c.still >= settings_.rest_ticks) {
      fall_asleep(i, coils[i]);
      changed = true;
    }
  }
  for (std::size_t i = 0; i < coils.size(); ++i) {
    Coil& c = coils_[i];
    if (!c.asleep || step_disturb_[i] == 0.0) continue;
    c.disturbed += step_disturb_[i];
    if (c.disturbed > settings_.wake_move_mm) {
      c = Coil{};
      ++wakes_;
      changed = true;
    }
  }
  if (changed) rebuild_chunks(coils);
}

}  // namespace cathbox::tool
