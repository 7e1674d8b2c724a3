#include "tool/lumen_axis.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::tool {
namespace {
// A foot in this many pieces of a segment's end also looks into the segments meeting there.
constexpr std::uint32_t kEndPieces = 3;
}  // namespace

LumenAxis::LumenAxis(const vessel::VesselModel& model)
    : model_(model), at_start_(model.segments.size()), at_end_(model.segments.size()) {
  const auto index = [&](std::int32_t id) -> std::int32_t {
    const std::optional<std::size_t> i = model_.index_of(id);
    return i ? static_cast<std::int32_t>(*i) : -1;
  };
  // At a segment's start meet its parents' ends and its siblings' starts; at its end its
  // children's starts and their other parents' ends.
  const auto add = [](std::vector<Neighbour>& to, std::int32_t s, bool from_start, std::size_t self) {
    if (s < 0 || static_cast<std::size_t>(s) == self) return;
    for (const Neighbour& n : to) {
      if (n.segment == s && n.from_start == from_start) return;
    }
    to.push_back({s, from_start});
  };
  for (std::size_t i = 0; i < model_.segments.size(); ++i) {
    const vessel::Segment& seg = model_.segments[i];
    for (const std::int32_t parent : seg.parents) {
      const std::int32_t p = index(parent);
      add(at_start_[i], p, false, i);
      if (p < 0) continue;
      for (const std::int32_t sibling : model_.segments[static_cast<std::size_t>(p)].children) add(at_start_[i], index(sibling), true, i);
    }
    for (const std::int32_t child : seg.children) {
      const std::int32_t c = index(child);
      add(at_end_[i], c, true, i);
      if (c < 0) continue;
      for (const std::int32_t other : model_.segments[static_cast<std::size_t>(c)].parents) add(at_end_[i], index(other), false, i);
    }
  }
}

std::uint32_t LumenAxis::pieces(std::int32_t s) const {
  const std::size_t n = model_.segments[static_cast<std::size_t>(s)].points.size();
  return n > 1 ? static_cast<std::uint32_t>(n - 1) : 1;
}

LumenAxis::Foot LumenAxis::on_piece(std::int32_t s, std::uint32_t piece, const glm::dvec3& p) const {
  const std::vector<vessel::CenterlinePoint>& pts = model_.segments[static_cast<std::size_t>(s)].points;
  Foot f;
  f.segment = s;
  f.piece = piece;
  if (pts.empty()) return f;
  const vessel::CenterlinePoint& a = pts[piece];
  const vessel::CenterlinePoint& b = piece + 1 < pts.size() ? pts[piece + 1] : a;
  const glm::dvec3 d = b.pos_mm - a.pos_mm;
  const double len2 = glm::dot(d, d);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a.pos_mm, d) / len2, 0.0, 1.0) : 0.0;
  f.foot_mm = a.pos_mm + t * d;
  f.radius_mm = a.radius_mm + t * (b.radius_mm - a.radius_mm);
  f.value = f.radius_mm - glm::distance(p, f.foot_mm);
  return f;
}

// The best piece of segment s from `piece` on, stepping to a neighbouring piece while it is better.
LumenAxis::Foot LumenAxis::climb(std::int32_t s, std::uint32_t piece, const glm::dvec3& p) const {
  const std::uint32_t n = pieces(s);
  Foot best = on_piece(s, std::min(piece, n - 1), p);
  for (int dir : {-1, 1}) {
    for (;;) {
      const std::int64_t next = static_cast<std::int64_t>(best.piece) + dir;
      if (next < 0 || next >= static_cast<std::int64_t>(n)) break;
      const Foot f = on_piece(s, static_cast<std::uint32_t>(next), p);
      if (!(f.value > best.value)) break;
      best = f;
    }
  }
  return best;
}

LumenAxis::Foot LumenAxis::scan(const glm::dvec3& p) const {
  Foot best;
  for (std::size_t s = 0; s < model_.segments.size(); ++s) {
    if (model_.segments[s].points.empty()) continue;
    const auto si = static_cast<std::int32_t>(s);
    for (std::uint32_t i = 0; i < pieces(si); ++i) {
      const Foot f = on_piece(si, i, p);
      if (f.value > best.value) best = f;
    }
  }
  return best;
}

glm::dvec3 LumenAxis::outward(const Foot& f, const glm::dvec3& p) const {
  const glm::dvec3 out_dir = p - f.foot_mm;
  const double d = glm::length(out_dir);
  if (d > 1e-9) return out_dir / d;
  // On the axis: any direction across the piece.
  const std::vector<vessel::CenterlinePoint>& pts = model_.segments[static_cast<std::size_t>(f.segment)].points;
  const glm::dvec3 along = pts.size() > f.piece + 1 ? pts[f.piece + 1].pos_mm - pts[f.piece].pos_mm : glm::dvec3(0.0, 0.0, 1.0);
  const glm::dvec3 other = std::abs(along.x) < 0.9 * glm::length(along) ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
  return glm::normalize(glm::cross(along, other));
}

LumenAxis::Answer LumenAxis::probe(const WallProbe& probe, AxisHint& hint, WallContact& out) const {
  const glm::dvec3& p = probe.center_mm;
  Foot best;
  if (hint.segment < 0 || static_cast<std::size_t>(hint.segment) >= model_.segments.size() ||
      glm::distance(p, hint.scanned_at_mm) > kRescan_mm) {
    best = scan(p);
    hint.scanned_at_mm = p;
  } else {
    best = climb(hint.segment, hint.piece, p);
  }
  if (best.segment < 0) return Answer::kNone;
  // The segments meeting at the end of the best one's that the foot is near: the best piece of each.
  std::array<Foot, kMostNear> near{};
  std::size_t count = 0;
  const auto look = [&](const std::vector<Neighbour>& at) {
    for (const Neighbour& nb : at) {
      if (count == near.size() || model_.segments[static_cast<std::size_t>(nb.segment)].points.empty()) continue;
      near[count++] = climb(nb.segment, nb.from_start ? 0U : pieces(nb.segment) - 1, p);
    }
  };
  const auto s = static_cast<std::size_t>(best.segment);
  if (best.piece < kEndPieces) look(at_start_[s]);
  if (best.piece + kEndPieces >= pieces(best.segment)) look(at_end_[s]);
  for (std::size_t i = 0; i < count; ++i) {
    if (near[i].value > best.value) std::swap(near[i], best);
  }
  hint.segment = best.segment;
  hint.piece = best.piece;
  // The smooth union: value tau log sum exp(v / tau) over them, normal the weighted mean of
  // their outward directions (the value's gradient): the inner corner of a junction rounded
  // over ~kBlend_mm, a single tube's answer exactly where the others are far.
  double sum = 1.0;
  glm::dvec3 dir = outward(best, p);
  for (std::size_t i = 0; i < count; ++i) {
    const double w = std::exp((near[i].value - best.value) / kBlend_mm);
    if (w < 1e-6) continue;
    sum += w;
    dir += w * outward(near[i], p);
  }
  const double value = best.value + kBlend_mm * std::log(sum);
  const double len = glm::length(dir);
  const glm::dvec3 normal = len > 1e-9 ? dir / len : outward(best, p);
  out.normal = normal;
  out.point_mm = p + normal * value;
  out.distance_mm = value;
  out.has_second = false;
  out.segment = model_.segments[static_cast<std::size_t>(best.segment)].id;
  return value - probe.radius_mm <= probe.range_mm ? Answer::kWall : Answer::kClear;
}

}  // namespace cathbox::tool
