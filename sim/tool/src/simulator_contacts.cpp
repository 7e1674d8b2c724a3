// Which rods are solved against each other (RodContactField members): coils past their
// detachment zone, released coils, the tips of the catheters coils leave, the working length of
// an inflated balloon (against coils only), and a lone tool against its own far parts.
#include "tool/simulator.hpp"

#include <algorithm>

namespace cathbox::tool {

namespace {
constexpr double kCatheterTipContact_mm = 3.0;  // the catheter's distal length coils can touch
// A coil's free part is listed in the rod-contact field from an edge a multiple of this
// (RodContactField::Member::listed_first), the edges inside its catheter before it listed but
// never gathered: its list survives 15 of 16 node crossings at the catheter's tip.
constexpr std::size_t kListedEdgeBlock = 16;
// prepare_next_step builds the list again once an edge's middle has moved this share of the half
// skin the list covers (a pushed coil's tip edges move 0.02 mm a tick against 0.15 mm).
constexpr double kPrepareShare = 0.7;
}  // namespace

// A tool with no catheter around it and none inside it (not a coil).
bool Simulator::lone(std::size_t t) const {
  const std::size_t n = rods_.size();
  return rods_[t].spec().kind != ToolKind::kCoil && outer_of_[t] >= n && carrier_[t] >= n &&
         std::none_of(outer_of_.begin(), outer_of_.end(), [t](std::size_t o) { return o == t; });
}

bool Simulator::balloon_guide(std::size_t c) const {
  return outer_of_[c] >= rods_.size() && specs_[c].steered_by_inner == InnerSteering::kAlways;
}

// Whether stent retriever u is part out of its catheters, part crimped in them: being unsheathed
// or drawn back in, the catheter's tip sliding over the crimp. Wholly inside (no node of it free:
// the M1 case's stent in the microcatheter's hub while it is advanced over the wire) or wholly
// out, it is not.
bool Simulator::unsheathing(std::size_t u) const {
  if (!specs_[u].stent.present() || !stents_[u]) return false;
  const Rod& rod = rods_[u];
  if (rod.first_free_node() >= rod.node_total()) return false;
  return stents_[u]->state().unsheathed_mm < specs_[u].stent.length_mm - 1e-9;
}

// An unconverged tick is solved again in sub-increments (Rod::step) for a lone tool and for a
// tool carried in a catheter (a guidewire carrying nothing, a catheter, an attached coil) while
// neither it nor any catheter around it is steered by what it carries (steered_now), no stent
// on it is being unsheathed (convergence.md, "Sub-stepped ticks",
// "Sub-stepped carried wires", "Sub-stepped carried catheters and coils": a stent retriever's
// re-solves while unsheathed cost the stent case's p99 several ticks; a steered stack's path
// left main's in the thrombectomy run; "Catheters hinged at the entry": wholly out, as in its
// retrieval, it is sub-stepped). In a stack whose
// only steerable catheter is its outermost one, a balloon guide, that guide's steering does not
// hold the tools inside it back (convergence.md, "Sub-stepped under a balloon guide"); in any
// balloon guide's stack, no steering holds back a wire, a coil or a catheter its wire steers
// (convergence.md, "An aspiration stack sub-stepped"). A stent retriever does not hold back a
// catheter its wire steers, in its hub, being unsheathed from it or wholly out ("The stent
// retriever's microcatheter sub-stepped", "The stent's microcatheter sub-stepped while the stent
// is unsheathed").
bool Simulator::substepped(std::size_t t) const {
  if (lone(t)) return true;
  const std::size_t n = rods_.size();
  if (outer_of_[t] >= n) return false;
  // A catheter in a balloon guide's stack (the aspiration stacks' aspiration catheter and
  // microcatheter) is sub-stepped while it is steered too: its inner tools' push on its tip is a
  // lagged load, the same in each part (convergence.md, "An aspiration stack sub-stepped").
  const std::size_t holder = outer_of_[t];
  std::size_t outermost = holder;
  for (std::size_t guard = 0; outer_of_[outermost] < n && guard <= n; ++guard) outermost = outer_of_[outermost];
  const bool in_guide = balloon_guide(holder);
  const bool guide_stack = balloon_guide(outermost);
  if (steered_now(t) && !guide_stack) return false;
  const ToolKind kind = specs_[t].kind;
  const bool carries = std::any_of(outer_of_.begin(), outer_of_.end(), [t](std::size_t o) { return o == t; });
  if (!(kind == ToolKind::kCatheter || kind == ToolKind::kCoil || (kind == ToolKind::kGuidewire && !carries))) {
    return false;
  }
  if (specs_[t].stent.present() && unsheathing(t)) return false;
  // A stent retriever inside keeps back only a catheter its wire does not steer (a case file's
  // microcatheter carrying one in a plain guide: not measured sub-stepped; no bundled case has
  // one since the Solumbra stacks' microcatheter is steered, record format 36).
  if (specs_[t].steered_by_inner == InnerSteering::kNone) {
    for (std::size_t u = 0; u < n; ++u) {
      if (u != t && nested_in(u, t) && specs_[u].stent.present()) return false;
    }
  }
  // In a balloon guide's stack no catheter's steering, the guide's or one advanced over it, holds
  // back a wire, a coil or a catheter its wire steers (the ADAPT run's microwire, held back while
  // its microcatheter was advanced, went unconverged and steered that microcatheter into the wall;
  // the microcatheter, held back while the aspiration catheter was advanced over it, was
  // unconverged on 1.2 % of its ticks: convergence.md, "An aspiration stack sub-stepped").
  if (guide_stack && (kind != ToolKind::kCatheter || specs_[t].steered_by_inner != InnerSteering::kNone)) return true;
  // Whether the only catheter round t that its inner tools can steer (t included) is the outermost
  // one, a balloon catheter: the stent retriever cases' balloon guide, not the aspiration stacks
  // (their aspiration catheter, steered while advanced, sits inside the guide).
  bool guided = false;
  for (std::size_t c = t, guard = 0; c < n && guard <= n; c = outer_of_[c], ++guard) {
    if (specs_[c].steered_by_inner == InnerSteering::kNone) continue;
    guided = balloon_guide(c);
    if (!guided) break;
  }
  // The guide's steering holds back only an unsteered catheter carried in another catheter within
  // it (sub-stepped, such a microcatheter left the wire's path for the PCom in the ADAPT run;
  // convergence.md, "An aspiration stack sub-stepped"), not the catheter directly in it.
  for (std::size_t c = holder, guard = 0; c < n && guard <= n; c = outer_of_[c], ++guard) {
    if (!steered_now(c)) continue;
    if (!(balloon_guide(c) && (guided || in_guide))) return false;
  }
  return true;
}

bool Simulator::prepare_next_step() { return contacts_.prepare(kPrepareShare); }

void Simulator::update_contact_members() {
  // Coils (their part past the detachment zone), released coils, and the tips of the
  // catheters coils leave.
  const std::size_t n = rods_.size();
  members_.clear();
  for (std::size_t t = 0; t < n; ++t) {
    const Rod& rod = rods_[t];
    if (rod.spec().kind != ToolKind::kCoil || removed_mm_[t] > 0.0 || rod.first_free_node() >= rod.node_total()) continue;
    std::size_t first = rod.first_edge();
    while (first + 1 < rod.node_total() && rod.node_from_tip_mm(first) > rod.spec().detach_mm + 1e-9) ++first;
    RodContactField::Member m;
    m.rod = &rod;
    m.edge_first = first;
    m.listed_first = first / kListedEdgeBlock * kListedEdgeBlock;
    m.edge_last = rod.node_total() - 1;
    m.self = true;
    m.coil = true;
    const std::size_t c = carrier_[t];
    if (c < n) {
      m.hollow = &rods_[c];
      m.hollow_depth_mm = 2.0 * (rod.node_radius_mm(rod.node_total() - 1) + rods_[c].radius_at_mm(0.0)) + 0.5;
    }
    if (m.edge_first < m.edge_last) members_.push_back(m);
  }
  // A lone tool (no catheter around it, none inside it) against its own far parts: a wire
  // buckled into a dead end folds onto itself (its tip passed through its shaft without this).
  for (std::size_t t = 0; t < n; ++t) {
    const Rod& rod = rods_[t];
    if (!lone(t) || rod.first_free_node() >= rod.node_total()) continue;
    RodContactField::Member m;
    m.rod = &rod;
    m.edge_first = rod.first_edge();
    m.edge_last = rod.node_total() - 1;
    m.self = true;
    m.self_only = true;  // two lone tools side by side are not solved against each other
    if (m.edge_first < m.edge_last) members_.push_back(m);
  }
  const bool coils = !members_.empty() || !detached_.empty();
  if (!coils) {
    contacts_.set_members(members_);
    return;
  }
  // The released coils by their views: the attached tools' field reads them while their own
  // solves run beside (simulator_released.cpp).
  for (const Rod& coil : coil_views_) {
    RodContactField::Member m;
    m.rod = &coil;
    m.edge_first = 0;
    m.edge_last = coil.node_total() - 1;
    m.self = true;
    m.coil = true;
    m.frozen = true;  // solved by the job, never gathered here
    members_.push_back(m);
  }
  for (std::size_t t = 0; t < n; ++t) {
    bool carries = false;
    for (std::size_t u = 0; u < n; ++u) {
      carries = carries || (rods_[u].spec().kind == ToolKind::kCoil && outer_of_[u] == t);
    }
    const Rod& rod = rods_[t];
    if (!carries || rod.first_free_node() >= rod.node_total()) continue;
    RodContactField::Member m;
    m.rod = &rod;
    m.edge_first = rod.first_edge();
    while (m.edge_first + 1 < rod.node_total() && rod.node_from_tip_mm(m.edge_first) > kCatheterTipContact_mm) ++m.edge_first;
    m.edge_last = rod.node_total() - 1;
    if (m.edge_first < m.edge_last) members_.push_back(m);
  }
  add_balloon_members();
  contacts_.set_members(members_);
}

// An inflated balloon (any pressure above none) against the coils: the edges whose middle lies
// on its working length, as capsules of its present diameter (its compliance chart). Deflated it
// is no member: the coils pass its shaft as they pass every catheter's but their own.
void Simulator::add_balloon_members() {
  if (std::none_of(members_.begin(), members_.end(), [](const RodContactField::Member& m) { return m.coil; })) return;
  for (std::size_t t = 0; t < rods_.size(); ++t) {
    if (!balloons_[t] || !(balloons_[t]->pressure_atm() > 0.0)) continue;
    const Rod& rod = rods_[t];
    if (rod.first_free_node() >= rod.node_total()) continue;
    const double lo = balloons_[t]->spec().from_tip_mm;
    const double hi = lo + balloons_[t]->spec().length_mm;
    const auto middle = [&](std::size_t e) { return 0.5 * (rod.node_from_tip_mm(e) + rod.node_from_tip_mm(e + 1)); };
    RodContactField::Member m;
    m.rod = &rod;
    m.edge_first = rod.first_edge();
    while (m.edge_first + 1 < rod.node_total() && middle(m.edge_first) > hi) ++m.edge_first;
    m.edge_last = m.edge_first;
    while (m.edge_last + 1 < rod.node_total() && middle(m.edge_last) >= lo) ++m.edge_last;
    m.radius_mm = 0.5 * balloons_[t]->diameter_mm();
    if (m.edge_first >= m.edge_last) continue;
    // One member a rod: a lone balloon catheter's contact with its own far parts gives way
    // while its balloon is inflated (gripping the wall, it does not fold onto itself).
    std::erase_if(members_, [&](const RodContactField::Member& o) { return o.rod == &rod; });
    members_.push_back(m);
  }
}

}  // namespace cathbox::tool
