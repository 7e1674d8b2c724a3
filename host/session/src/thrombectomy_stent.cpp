// The thrombectomy unit's stent retriever passes (thrombectomy_unit.hpp): deployment across a
// clot, integration over the dwell, retrieval, and the pass's outcome at the catheter it
// ends in.
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include <glm/geometric.hpp>
#include <glm/common.hpp>

#include "flow/aspiration.hpp"
#include "flow/clot_fracture.hpp"
#include "session/thrombectomy_unit.hpp"
#include "tool/stent_retriever.hpp"

namespace cathbox::session {
namespace {

constexpr double kRetryMove_mm = 0.5;         // a stent out of its catheter over no clot is looked at again past this
constexpr double kIntegratedShare = 0.95;     // logged once reached

// Back to a stent in its catheter (the tool and its device kept).
template <class Pass>
void reset(Pass& p) {
  Pass fresh;
  fresh.tool = p.tool;
  fresh.spec = p.spec;
  p = std::move(fresh);
}

// The node parameter from the tip (0 at the last node; j + f a fraction f of the way from the
// j-th node back from the tip to the next) of the point of the polyline `nodes` (tip last)
// nearest to `p`.
double param_from_tip(std::span<const glm::dvec3> nodes, const glm::dvec3& p) {
  double best = 0.0;
  double best_d2 = std::numeric_limits<double>::infinity();
  const std::size_t n = nodes.size();
  for (std::size_t j = 0; j + 1 < n; ++j) {
    const glm::dvec3& a = nodes[n - 1 - j];
    const glm::dvec3 ab = nodes[n - 2 - j] - a;
    const double len2 = glm::dot(ab, ab);
    const double f = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    const glm::dvec3 q = a + f * ab;
    if (const double d2 = glm::dot(p - q, p - q); d2 < best_d2) {
      best_d2 = d2;
      best = static_cast<double>(j) + f;
    }
  }
  return best;
}

// The point at node parameter `u` from the tip of `nodes` (tip last), clamped to the polyline.
glm::dvec3 point_from_tip(std::span<const glm::dvec3> nodes, double u) {
  const std::size_t n = nodes.size();
  if (n < 2) return n == 1 ? nodes[0] : glm::dvec3(0.0);
  const double at = std::clamp(u, 0.0, static_cast<double>(n - 1));
  const auto j = std::min(static_cast<std::size_t>(at), n - 2);
  return glm::mix(nodes[n - 1 - j], nodes[n - 2 - j], at - static_cast<double>(j));
}

}  // namespace

double ThrombectomyUnit::stent_integration(std::size_t tool) const {
  for (const StentPass& p : stents_) {
    if (p.tool == tool && p.deployed) return p.integration;
  }
  return 0.0;
}

bool ThrombectomyUnit::stent_retrieving(std::size_t tool) const {
  return std::any_of(stents_.begin(), stents_.end(), [tool](const StentPass& p) { return p.tool == tool && p.retrieving; });
}

void ThrombectomyUnit::after_step(std::int64_t time_us, tool::Simulator& sim) {
  retrieval_pull_mN_ = 0.0;
  for (StentPass& p : stents_) stent_step(p, time_us, sim);
  for (const Aspirator& a : aspirators_) {
    const double grip_mN = aspiration_grip_mN(a.tool);
    if (grip_mN != sim.tip_grip_mN(a.tool)) sim.set_tip_grip(a.tool, grip_mN);
  }
}

double ThrombectomyUnit::aspiration_grip_mN(std::size_t tool) const {
  const Aspirator* a = aspirator(tool);
  if (!hold_.on(tool) || hold_.thrombus().empty() || !all_remain(hold_.thrombus()) || a == nullptr) return 0.0;
  return a->grip_mN(thrombus_clot(hold_.thrombus()), head_Pa(clot_of(hold_.thrombus().front())));
}

// The clot the stent's unsheathed nodes lie in and the share of its thrombus they cover:
// per clot the span between the first and last node inside it (each node standing for half
// its spacing either way), over the thrombus's length.
ThrombectomyUnit::StentCover ThrombectomyUnit::stent_cover(const tool::Simulator& sim, std::size_t tool) const {
  StentCover out;
  const tool::StentRetriever* device = sim.stent(tool);
  const tool::Rod& rod = sim.rod(tool);
  const std::size_t n = rod.node_total();
  const std::size_t first = device->state().first_node;
  if (first >= n) return out;
  const double half_spacing_mm = first + 1 < n ? 0.5 * (rod.node_from_tip_mm(first) - rod.node_from_tip_mm(first + 1)) : 0.0;
  std::vector<double> covered(clots_.size(), 0.0);
  for (std::size_t k = 0; k < clots_.size(); ++k) {
    const flow::Clot& c = clots_[k];
    double lo = c.arc_start_mm + c.length_mm;
    double hi = c.arc_start_mm;
    for (std::size_t i = first; i < n; ++i) {
      const flow::CenterlinePosition on = locator_.nearest_on(c.segment, rod.positions()[i]);
      if (on.arc_mm < c.arc_start_mm - half_spacing_mm || on.arc_mm > c.arc_start_mm + c.length_mm + half_spacing_mm ||
          on.distance_mm > locator_.radius_at(c.segment, on.arc_mm)) {
        continue;
      }
      lo = std::min(lo, on.arc_mm - half_spacing_mm);
      hi = std::max(hi, on.arc_mm + half_spacing_mm);
    }
    covered[k] = std::max(0.0, std::min(hi, c.arc_start_mm + c.length_mm) - std::max(lo, c.arc_start_mm));
    if (covered[k] > 0.0 && out.thrombus.empty()) out.thrombus = thrombus_of(k);
  }
  if (out.thrombus.empty()) return out;
  double total_mm = 0.0;
  double under_mm = 0.0;
  for (const ClotId id : out.thrombus) {
    const std::size_t k = *index_of(id);
    total_mm += clots_[k].length_mm;
    under_mm += covered[k];
  }
  out.share = total_mm > 0.0 ? std::min(1.0, under_mm / total_mm) : 0.0;
  return out;
}

void ThrombectomyUnit::stent_step(StentPass& p, std::int64_t time_us, tool::Simulator& sim) {
  const tool::StentRetriever* device = sim.stent(p.tool);
  if (device == nullptr) return;
  const double dt_s = p.last_us >= 0 ? static_cast<double>(time_us - p.last_us) * 1e-6 : 0.0;
  p.last_us = time_us;
  const tool::StentState& st = device->state();
  const double insertion = sim.insertion_mm(p.tool);
  if (p.retrieving) {
    // The pull of converged steps only (an unconverged step's forces are not an equilibrium's:
    // host/session/README.md, "Wall forces").
    if (sim.rod(p.tool).converged()) {
      const double pull_mN = std::max(0.0, -sim.hand_force_mN(p.tool));
      p.peak_pull_mN = std::max(p.peak_pull_mN, pull_mN);
      retrieval_pull_mN_ = std::max(retrieval_pull_mN_, pull_mN);
    }
    if (st.unsheathed_mm <= 0.0) end_stent_pass(p, time_us, sim);
    return;
  }
  const bool expanded = st.unsheathed_mm >= 0.5 * p.spec.length_mm;
  if (!p.deployed) {
    const bool moved = std::abs(st.unsheathed_mm - p.tried_unsheathed_mm) > kRetryMove_mm || std::abs(insertion - p.tried_insertion_mm) > kRetryMove_mm;
    if (expanded && moved) deploy_stent(p, time_us, sim);
    return;
  }
  if (insertion < p.deployed_insertion_mm - kStentRetrievalStart_mm) {
    start_retrieval(p, time_us, sim);
    return;
  }
  if (std::abs(st.unsheathed_mm - p.tried_unsheathed_mm) > kRetryMove_mm) {  // more of it out: what it covers now
    p.tried_unsheathed_mm = st.unsheathed_mm;
    const StentCover cover = stent_cover(sim, p.tool);
    if (!cover.thrombus.empty()) p.cover = std::max(p.cover, cover.share);
  }
  if (!expanded) {  // the catheter pushed back over it in place: nothing retrieved
    log(time_us, "stent retriever re-sheathed in place: the clot is let go");
    reset(p);
    return;
  }
  if (std::abs(insertion - p.deployed_insertion_mm) <= kStentStill_mm) {
    const double before = p.integration;
    p.dwell_s += dt_s;
    p.integration = tool::stent_integration(p.spec, p.dwell_s);
    if (before < kIntegratedShare && p.integration >= kIntegratedShare) {
      log(time_us, "stent retriever: the clot is %.0f %% integrated after %.0f s", 100.0 * p.integration, p.dwell_s);
    }
  }
}

void ThrombectomyUnit::deploy_stent(StentPass& p, std::int64_t time_us, const tool::Simulator& sim) {
  const tool::StentState& st = sim.stent(p.tool)->state();
  p.tried_unsheathed_mm = st.unsheathed_mm;
  p.tried_insertion_mm = sim.insertion_mm(p.tool);
  const StentCover cover = stent_cover(sim, p.tool);
  if (cover.thrombus.empty()) return;
  p.deployed = true;
  p.thrombus = cover.thrombus;  // drawn engaged (start_retrieval looks again)
  p.cover = cover.share;
  p.deployed_insertion_mm = sim.insertion_mm(p.tool);
  p.dwell_s = 0.0;
  p.integration = 0.0;
  log(time_us, "stent retriever across the clot in the %s: %.0f %% covered, %.1f-%.1f mm, %.2f N radial",
      segment_name(clot_of(cover.thrombus.front()).segment).c_str(), 100.0 * cover.share, st.min_diameter_mm, st.max_diameter_mm,
      st.radial_force_N);
}

void ThrombectomyUnit::start_retrieval(StentPass& p, std::int64_t time_us, tool::Simulator& sim) {
  const StentCover cover = stent_cover(sim, p.tool);
  p.retrieving = true;
  p.peak_pull_mN = sim.rod(p.tool).converged() ? std::max(0.0, -sim.hand_force_mN(p.tool)) : 0.0;
  retrieval_pull_mN_ = std::max(retrieval_pull_mN_, p.peak_pull_mN);
  if (cover.thrombus.empty()) {  // it has moved off the clot (or the clot went in another pass)
    p.captured = false;
    log(time_us, "stent retrieval: no clot under the stent");
    return;
  }
  p.thrombus = cover.thrombus;
  p.cover = std::max(p.cover, cover.share);
  const flow::AspirationClot clot = thrombus_clot(p.thrombus);
  const double head = head_Pa(clot_of(p.thrombus.front()));
  const double grip_N = p.integration * p.cover * tool::stent_capture_force_N(p.spec);
  const double hold_N = flow::clot_hold_force_N(clot, head);
  p.captured = grip_N > hold_N;
  if (p.captured) {
    sim.set_stent_payload(p.tool, 1000.0 * flow::clot_drag_force_N(clot, head));
    hold_on_stent(p, sim.rod(p.tool).positions());
  }
  log(time_us, "stent retrieval: the clot %s (grip %.3f N: %.0f %% integrated, %.0f %% covered; held by %.3f N)",
      p.captured ? "comes with the stent" : "slips out of the stent", grip_N, 100.0 * p.integration, 100.0 * p.cover, hold_N);
}

void ThrombectomyUnit::end_stent_pass(StentPass& p, std::int64_t time_us, tool::Simulator& sim) {
  sim.set_stent_payload(p.tool, 0.0);
  const int pass = ++figures_.passes;
  ++figures_.stent_passes;
  figures_.retrieval_force_peak_N = std::max(figures_.retrieval_force_peak_N, 1e-3 * p.peak_pull_mN);
  const std::size_t into = sim.carrier(p.tool);
  const std::string into_name = into < tool_names_.size() ? tool_names_[into] : std::string("vessel");
  log(time_us, "pass %d: the stent retriever is back in the %s (peak pull %.3f N)", pass, into_name.c_str(), 1e-3 * p.peak_pull_mN);
  std::vector<ClotId> removed;
  std::vector<flow::Fragment> fragments;
  const bool held = p.captured && !p.thrombus.empty() && all_remain(p.thrombus);
  if (!held || into >= tool_names_.size()) {
    log(time_us, "pass %d: the clot stays", pass);
  } else {
    removed = p.thrombus;
    const flow::AspirationClot clot = thrombus_clot(p.thrombus);
    const flow::CenterlinePosition at = mouth(into);
    const double id_mm = inner_diameter_[into];
    if (into == sim.outer_of(p.tool)) {
      // Re-sheathed in its own microcatheter: the tip strips the clot off the struts and lets it
      // go there, into the flow, in the pieces the flow's shear tears it into.
      fragments = flow::fragments_in_flow({at, clot.diameter_mm, clot.length_mm, clot.composition}, flow::wall_shear_Pa(network_, at));
      log(time_us, "pass %d: re-sheathed in the %s, the clot is stripped off into the flow", pass, into_name.c_str());
    } else if (clot.diameter_mm > id_mm && (aspirating_[into] != 0 || arrests_.empty())) {
      // Wider than the mouth: the mouth shears the rim off, into the flow there; an aspirating
      // catheter's own sink draws it in when it out-draws every branch at its node. (Under flow
      // arrest without aspiration the rim stays in the arrested column: a rule, README.)
      const double rim_mm = clot.diameter_mm - id_mm;
      fragments.push_back({at, rim_mm, std::min(clot.length_mm, rim_mm), clot.composition});
      log(time_us, "pass %d: the clot comes out; the %s's mouth shears a %.2f mm rim off it", pass, into_name.c_str(), rim_mm);
    } else {
      log(time_us, "pass %d: the clot comes out in the %s%s", pass, into_name.c_str(),
          aspirating_[into] != 0 ? " under aspiration" : (arrests_.empty() ? "" : " under flow arrest"));
    }
  }
  reset(p);
  grade_pass(time_us, removed, fragments);
}

// Where each clot of the captured thrombus lies on the stent (its face and end as node
// parameters of the rod's nodes `x`), and the stent's nodes as far back as the furthest of them.
// Allocates: an event, once a retrieval.
void ThrombectomyUnit::hold_on_stent(StentPass& p, std::span<const glm::dvec3> x) const {
  p.on_stent.clear();
  double furthest = 0.0;
  for (const ClotId k : p.thrombus) {
    const flow::Clot& c = clot_of(k);
    const double face = param_from_tip(x, locator_.point_at(c.segment, c.arc_start_mm));
    const double end = param_from_tip(x, locator_.point_at(c.segment, c.arc_start_mm + c.length_mm));
    p.on_stent.push_back({face, end});
    furthest = std::max({furthest, face, end});
  }
  const std::size_t keep = std::min(x.size(), static_cast<std::size_t>(furthest) + 2);
  p.path.assign(x.end() - static_cast<std::ptrdiff_t>(keep), x.end());
}

ClotView ThrombectomyUnit::clot_view(std::size_t k) const {
  const flow::Clot& c = clots_[k];
  ClotView v;
  v.radius_mm = static_cast<float>(locator_.radius_at(c.segment, c.arc_start_mm + 0.5 * c.length_mm));
  const ClotId id = clot_ids_[k];
  if (hold_.holds(id)) v.state = ClotState::kEngaged;
  const StentPass* drag = nullptr;
  std::size_t slot = 0;
  for (const StentPass& p : stents_) {
    const auto at = std::find(p.thrombus.begin(), p.thrombus.end(), id);
    if (!p.deployed || at == p.thrombus.end()) continue;
    v.state = ClotState::kEngaged;
    slot = static_cast<std::size_t>(at - p.thrombus.begin());
    if (p.retrieving && p.captured && slot < p.on_stent.size() && !p.path.empty()) {
      v.state = ClotState::kDragged;
      drag = &p;
    }
  }
  for (int i = 0; i < ClotView::kAxisPoints; ++i) {
    const double f = static_cast<double>(i) / (ClotView::kAxisPoints - 1);
    const glm::dvec3 at = drag != nullptr ? point_from_tip(drag->path, glm::mix(drag->on_stent[slot][0], drag->on_stent[slot][1], f))
                                          : locator_.point_at(c.segment, c.arc_start_mm + f * c.length_mm);
    v.axis_mm[static_cast<std::size_t>(i)] = glm::vec3(at);
  }
  v.start_mm = v.axis_mm.front();
  v.end_mm = v.axis_mm.back();
  return v;
}

}  // namespace cathbox::session
