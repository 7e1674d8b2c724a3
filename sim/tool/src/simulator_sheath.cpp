// The simulator's sheath paths: the lumens of the catheters around a tool, and their friction.
#include "tool/simulator.hpp"

#include "sheath_anchor.hpp"
#include "simulator_tuning.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::tool {

namespace {

// The inner tool's covered part a sheath path is built for: its tip and where its covered part
// ends (depths from the entry), and the station the holders' lumen radius was last read at.
struct SheathSpan {
  const Rod& inner;
  double tip_mm;
  double end_mm;
  std::size_t station = Rod::kNoStation;
};

// A vertex of the path at `p` on holder `h` (its free part starting `free_start` deep). A holder's
// first free node (just past its entry: the carrier's tip, or the entry) fades in over its first
// edge, in position (from the entry line, where it crossed, to its own place) and in weight
// (SheathVertex::weight): it joins the path where its clamp left it and takes its lateral play and
// its share of the turning in proportion to the length it is out. The rule before (the entry's
// vertex left out while the node was under half a spacing past it, then put back) stepped the
// coiling run's wire by 0.3-1.4 N in a tick at each of the microcatheter's nodes leaving the
// guide's tip.
SheathVertex sheath_vertex(SheathSpan& span, const Rod& h, double free_start, glm::dvec3 p, std::size_t holder,
                           std::size_t node, double depth, bool at_node) {
  double weight = 1.0;
  const std::size_t ff = h.first_free_node();
  if (at_node && node == ff && ff >= 2 && node < h.node_total()) {
    const double s = h.node_depth_mm(ff);
    const double edge = s - h.node_depth_mm(ff - 1);
    const glm::dvec3 back = h.positions()[ff - 1] - h.positions()[ff - 2];
    const double lb = glm::length(back);
    if (edge > 1e-9 && lb > 1e-12) {
      weight = std::clamp(s / edge, 0.0, 1.0);
      const glm::dvec3 on_line = h.positions()[ff - 1] + back * ((s - h.node_depth_mm(ff - 1)) / lb);
      p = on_line + (p - on_line) * weight;
    }
  }
  SheathVertex v;
  v.point_mm = p;
  v.holder = static_cast<std::uint32_t>(holder);
  v.node = static_cast<std::uint32_t>(node);
  v.depth_mm = depth;
  const double from_tip = span.tip_mm - std::min(depth, span.end_mm);
  const double holder_from_tip = h.insertion_mm() - (depth - free_start);
  v.inner_radius_mm = span.inner.radius_at_mm(from_tip);
  v.clearance_mm = std::max(0.0, h.inner_radius_at_mm(holder_from_tip, span.station) - v.inner_radius_mm);
  v.mu = h.spec().lumen_friction;
  v.weight = weight;
  return v;
}

}  // namespace

void Simulator::build_sheath_path(std::size_t u, std::vector<SheathVertex>& path) const {
  // From where the tool's covered part ends (its own part's clamp, or its tip) back to the
  // entry, along the free parts of the catheters around it, innermost first.
  path.clear();
  const std::size_t n = rods_.size();
  const Rod& inner = rods_[u];
  const double tip_u = tip_depth_mm(u);
  const double end = std::min(tip_u, free_start_[u]);
  if (end <= 0.0) return;
  SheathSpan span{inner, tip_u, end};
  const auto vertex = [&](glm::dvec3 p, std::size_t holder, std::size_t node, double depth, bool at_node) {
    path.push_back(sheath_vertex(span, rods_[holder], free_start_[holder], p, holder, node, depth, at_node));
  };
  // The distal end: the holder's node just past the inner tool's end (its tip node when the
  // inner tool leaves it), the vertex behind the end covering its turning in proportion.
  std::size_t first_holder = n;
  for (std::size_t c = outer_of_[u], guard = 0; c < n && guard <= n; c = outer_of_[c], ++guard) {
    if (end > free_start_[c] && end <= tip_depth_mm(c) + 1e-9) first_holder = c;
  }
  if (first_holder >= n) return;
  {
    const Rod& h = rods_[first_holder];
    std::size_t node = 0;
    const glm::dvec3 p = h.point_at_depth(end - free_start_[first_holder], nullptr, &node);
    const std::size_t b = std::min(node + 1, h.node_total() - 1);
    const double depth_b = free_start_[first_holder] + h.node_depth_mm(b);
    if (depth_b >= end - 1e-9) {
      vertex(h.positions()[b], first_holder, b, depth_b, true);
    } else {
      vertex(p, first_holder, b, end, false);
    }
  }
  // Every holder node behind the distal vertex follows it: on the first holder, every node short
  // of that vertex, which is the node past the end when point_at_depth put the end in the edge
  // distal of a node. A node on the end itself left out as past the end (as it was) lost its bend
  // for the tick the end sat on it: the pulled-back empty pusher's slip limit 117 mN shallower for
  // that one tick in the coiling run (27.455 / 40.155 s).
  const double distal_depth = std::max(end, path.front().depth_mm);
  for (std::size_t c = outer_of_[u], guard = 0; c < n && guard <= n; c = outer_of_[c], ++guard) {
    const Rod& h = rods_[c];
    const double lo = free_start_[c];
    const double hi = std::min(end, tip_depth_mm(c));
    if (hi <= lo) continue;
    const double past = c == first_holder ? distal_depth : end;
    for (std::size_t k = h.node_total(); k-- > h.first_free_node();) {
      const double depth = lo + h.node_depth_mm(k);
      if (depth >= past - 1e-9 || depth <= lo) continue;
      vertex(h.positions()[k], c, k, depth, true);
    }
  }
  // The entry.
  std::size_t outermost = u;
  for (std::size_t c = outer_of_[u], guard = 0; c < n && guard <= n; c = outer_of_[c], ++guard) outermost = c;
  vertex(entry_.point_mm, outermost, rods_[outermost].first_free_node(), 0.0, false);
  cover_sheath_path(inner, tip_u, end, path);
}

// The share of its turning the vertex behind the inner tool's end covers, and the inner tool's
// bending stiffness over each vertex's span (half its edges each way, up to the tool's end), its
// sections' compliances in series (Rod::vertex_bending_Nmm2): a turn concentrated at a vertex
// bends the tool's softer part there.
void Simulator::cover_sheath_path(const Rod& inner, double tip_mm, double end_mm, std::vector<SheathVertex>& path) {
  const std::size_t m = path.size();
  if (m >= 2) {
    const double edge = path[0].depth_mm - path[1].depth_mm;
    path[1].coverage = edge > 1e-9 ? std::clamp((end_mm - path[1].depth_mm) / edge, 0.0, 1.0) : 1.0;
  }
  // Depth d lies tip_mm - d from the tip: inner.length_mm() - (tip_mm - d) from the proximal end.
  const double proximal_at_tip = inner.length_mm() - tip_mm;
  // The stiffness at the vertex itself where its span is empty or holds an unbendable section:
  // looked up only then, walking the stations as the vertices go from the tip back.
  std::size_t station = Rod::kNoStation;
  for (std::size_t j = 0; j < m; ++j) {
    const double at = path[j].depth_mm;
    const double hi = std::min(j > 0 ? 0.5 * (at + path[j - 1].depth_mm) : at, end_mm);
    const double lo = j + 1 < m ? 0.5 * (at + path[j + 1].depth_mm) : at;
    constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    double ei = hi > lo + 1e-9 ? inner.vertex_bending_Nmm2(proximal_at_tip + lo, proximal_at_tip + hi, kNone) : kNone;
    if (std::isnan(ei)) ei = inner.bending_at_Nmm2(tip_mm - std::min(at, end_mm), station);
    path[j].inner_ei_Nmm2 = ei;
  }
}

// A balloon catheter always; an aspiration catheter (and a catheter it or a balloon guide carries)
// while its hand advances it (its tip deeper than the step before) or while a wire or catheter
// leaving its tip is drawn back into it (that tool's tip shallower than the step before; not a
// stent retriever: the careless M1 run's stent re-sheathed into its microcatheter read 0.381 N
// against 0.151, its cage's lean steering the tip it is stripped at). Drawn back, the
// tool's free part shortens, and its lean on the tip grows as its length falls: held by
// a tip that never gives, the ADAPT run's microcatheter drawn into its parked aspiration
// catheter, its last 1 mm pressed on the wall, read up to 1.1 N of clamp force, 1.0 N of it
// along the tip, and swung 150-570 mN a tick (convergence.md, "A carrier steered while its tool
// is drawn back"). Not while both are parked: the Solumbra microcatheter leaning on the parked
// aspiration catheter's tip stalled the stent's steps (docs/session/thrombectomy.md).
bool Simulator::steered_now(std::size_t c) const {
  switch (specs_[c].steered_by_inner) {
    case InnerSteering::kAlways: return true;
    case InnerSteering::kWhileAdvanced: return tip_depth_mm(c) > stepped_depth_[c] + 1e-9 || drawn_back_into(c);
    case InnerSteering::kNone: return false;
  }
  return false;
}

// A carrier steered while advanced (kWhileAdvanced), parked with a tool leaving its tip, keeps
// the steering push its last steered step left: nothing moved since, so the lean of the tool
// it carries on its tip is the lean it had. Relaxed away instead (as on a carrier that carries
// nothing out of its tip), the M1 Solumbra run's aspiration catheter, stopped at 100 mm over its
// microcatheter, sprang back into it: the microcatheter, held at that tip, was pressed into the
// wall at the contact cap (4,000 mN), its hand read 1.2 -> 3.9 N in 4 ticks and 8.3 N as its wire
// was drawn out (118 ticks over the box's 5 N); kept, 2.4 N and none (convergence.md, "A parked
// carrier keeps its tool's lean"). Still not steered by it while parked (the lean followed
// tick by tick stalled the Solumbra stent's steps: steered_now).
bool Simulator::tip_lean_held(std::size_t c) const {
  if (specs_[c].steered_by_inner != InnerSteering::kWhileAdvanced || steered_now(c)) return false;
  for (std::size_t u = 0; u < rods_.size(); ++u) {
    if (carrier_[u] == c && leaves_tip(u)) return true;
  }
  return false;
}

bool Simulator::leaves_tip(std::size_t u) const {
  const Rod& rod = rods_[u];
  return tip_depth_mm(u) > free_start_[u] && rod.first_free_node() < rod.node_total();
}

bool Simulator::drawn_back_into(std::size_t c) const {
  for (std::size_t u = 0; u < rods_.size(); ++u) {
    if (carrier_[u] == c && !specs_[u].stent.present() && tip_depth_mm(u) < stepped_depth_[u] - 1e-9) return true;
  }
  return false;
}

void Simulator::update_sheath(std::size_t u, double dt_s) {
  (void)dt_s;
  const std::size_t n = rods_.size();
  const Rod& rod = rods_[u];
  const std::size_t o = outer_of_[u];
  const bool has_free = leaves_tip(u);
  const double distal = has_free ? rod.clamp_read_mN() : 0.0;
  build_sheath_path(u, path_);
  const double slide = (tip_depth_mm(u) - stepped_depth_[u]) - (tip_depth_mm(o) - stepped_depth_[o]);
  const double turn = (rotation_[u] - stepped_rotation_[u]) - (rotation_[o] - stepped_rotation_[o]);
  const double k_anchor = sheath_anchor_mN_per_mm(rod, tip_depth_mm(u), rods_[o], tip_depth_mm(o));
  // A coil's push on the bends of the catheter it leaves (SheathFriction::set_bend_reaction),
  // while tuning::kCoilBendReaction says.
  sheath_[u].set_bend_reaction(tuning::kCoilBendReaction && rod.spec().kind == ToolKind::kCoil);
  // The axial force the capstan reads from the free part: no more than the free part's external
  // forces sum to (Rod::free_part_load_mN; the free-body balance). A clamp force beyond it is
  // held by nothing on the free part: the parked stent retriever's push wire, its first free
  // edges pressed by the withdrawn microcatheter's tip against nodes held at the wall, read up to
  // 771 N, whose capstan term stuck the friction and dragged the microcatheter (convergence.md,
  // "The M1 stent retriever's jumps, by cause"). The hand still feels distal + friction.
  const double carried = has_free ? rod.free_part_load_mN() : 0.0;
  const double read = std::clamp(distal, -carried, carried);
  sheath_result_[u] = sheath_[u].update(slide, turn, read, path_, k_anchor);
  const SheathFriction::Result& r = sheath_result_[u];
  hand_force_[u] = (has_free ? rod.hand_force_mN() : 0.0) + r.force_mN;
  // The inner tool leaves its carrier's tip clamped to it: what the clamp holds it with, across
  // the carrier's tip direction, is the inner tool's push on that tip (a wire bent out of a
  // catheter's tip into its path steers the tip after it; along the tip it is the inner tool's
  // push from the hand, which the sheath carries), on a carrier its ToolSpec::steered_by_inner
  // says is steered now (sim/tool README, "Coaxial tools"). The push of the inner tool's last
  // converged step: an unconverged one's clamp force is a leftover penetration's penalty (the
  // ADAPT run's microwire read up to 790 N on it, and its microcatheter, steered by it, snapped
  // into the wall at -20 N; convergence.md, "An aspiration stack sub-stepped").
  const std::size_t c = carrier_[u];
  if (has_free && rod.converged()) converged_clamp_[u] = rod.clamp_force_mN();
  if (has_free && c < n && steered_now(c)) {
    const glm::dvec3 along = rods_[c].tip().direction;
    const glm::dvec3 held = converged_clamp_[u];
    const glm::dvec3 lateral = held - along * glm::dot(held, along);
    if (std::isfinite(lateral.x + lateral.y + lateral.z)) {
      tip_push_[c] -= lateral * tuning::kTipPushRelaxation;
    }
  }
  hand_torque_[u] = (has_free ? rod.hand_torque_mNmm() : 0.0) + r.torque_mNmm;
  // The reaction onto the catheters' nodes.
  const std::vector<glm::dvec3>& reaction = sheath_[u].reaction_mN();
  for (std::size_t j = 0; j < path_.size() && j < reaction.size(); ++j) {
    const SheathVertex& v = path_[j];
    if (v.holder >= n || v.node >= coupling_next_[v.holder].size()) continue;
    if (v.node < rods_[v.holder].first_free_node()) continue;
    coupling_next_[v.holder][v.node] += reaction[j] * tuning::kCouplingRelaxation;
    coupling_set_[v.holder].add(v.node);
  }
}

}  // namespace cathbox::tool
