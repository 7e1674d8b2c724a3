// The thrombectomy unit's stent retriever passes (thrombectomy_unit.hpp): deployment across a
// clot, integration over the dwell, retrieval, and the pass's outcome at the catheter it
// ends in.
#include <algorithm>
#include <cmath>

#include "flow/aspiration.hpp"
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

}  // namespace

double ThrombectomyUnit::stent_integration(std::size_t tool) const {
  for (const StentPass& p : stents_) {
    if (p.tool == tool && p.deployed) return p.integration;
  }
  return 0.0;
}

void ThrombectomyUnit::after_step(std::int64_t time_us, tool::Simulator& sim) {
  for (StentPass& p : stents_) stent_step(p, time_us, sim);
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
  for (const std::size_t k : out.thrombus) {
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
    if (sim.rod(p.tool).converged()) p.peak_pull_mN = std::max(p.peak_pull_mN, -sim.hand_force_mN(p.tool));
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
      segment_name(clots_[cover.thrombus.front()].segment).c_str(), 100.0 * cover.share, st.min_diameter_mm, st.max_diameter_mm,
      st.radial_force_N);
}

void ThrombectomyUnit::start_retrieval(StentPass& p, std::int64_t time_us, tool::Simulator& sim) {
  const StentCover cover = stent_cover(sim, p.tool);
  p.retrieving = true;
  if (p.tool < tips_.size()) p.retrieval_tip_mm = tips_[p.tool];
  p.peak_pull_mN = sim.rod(p.tool).converged() ? std::max(0.0, -sim.hand_force_mN(p.tool)) : 0.0;
  if (cover.thrombus.empty()) {  // it has moved off the clot (or the clot went in another pass)
    p.captured = false;
    log(time_us, "stent retrieval: no clot under the stent");
    return;
  }
  p.thrombus = cover.thrombus;
  p.cover = std::max(p.cover, cover.share);
  const flow::AspirationClot clot = thrombus_clot(p.thrombus);
  const double head = head_Pa(clots_[p.thrombus.front()]);
  const double grip_N = p.integration * p.cover * tool::stent_capture_force_N(p.spec);
  const double hold_N = flow::clot_hold_force_N(clot, head);
  p.captured = grip_N > hold_N;
  if (p.captured) sim.set_stent_payload(p.tool, 1000.0 * flow::clot_drag_force_N(clot, head));
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
  std::vector<std::size_t> removed;
  std::optional<flow::Fragment> fragment;
  const bool held = p.captured && !p.thrombus.empty() &&
                    std::all_of(p.thrombus.begin(), p.thrombus.end(), [&](std::size_t k) { return k < clots_.size(); });
  if (!held) {
    log(time_us, "pass %d: the clot stays", pass);
  } else if (into >= tool_names_.size() || into == sim.outer_of(p.tool)) {
    log(time_us, "pass %d: re-sheathed in the %s, the clot is stripped off and stays", pass, into_name.c_str());
  } else {
    removed = p.thrombus;
    const flow::AspirationClot clot = thrombus_clot(p.thrombus);
    const double id_mm = inner_diameter_[into];
    if (clot.diameter_mm > id_mm && aspirating_[into] == 0 && arrests_.empty()) {
      // Wider than the mouth, nothing drawing it in and the flow running: the mouth shears the
      // rim off, and the flow carries it from there.
      fragment.emplace();
      fragment->from = locator_.nearest(tips_[into]);
      fragment->diameter_mm = clot.diameter_mm - id_mm;
      fragment->length_mm = std::min(clot.length_mm, fragment->diameter_mm);
      fragment->composition = clot.composition;
      log(time_us, "pass %d: the clot comes out; the %s's mouth shears a %.2f mm rim off it", pass, into_name.c_str(), fragment->diameter_mm);
    } else {
      log(time_us, "pass %d: the clot comes out in the %s%s", pass, into_name.c_str(),
          aspirating_[into] != 0 ? " under aspiration" : (arrests_.empty() ? "" : " under flow arrest"));
    }
  }
  reset(p);
  grade_pass(time_us, std::move(removed), fragment);
}

ClotView ThrombectomyUnit::clot_view(std::size_t k) const {
  const flow::Clot& c = clots_[k];
  glm::dvec3 shift(0.0);
  ClotState state = ClotState::kInPlace;
  if (engaged_tool_ && std::find(engaged_.begin(), engaged_.end(), k) != engaged_.end()) state = ClotState::kEngaged;
  for (const StentPass& p : stents_) {
    if (!p.deployed || std::find(p.thrombus.begin(), p.thrombus.end(), k) == p.thrombus.end()) continue;
    state = ClotState::kEngaged;
    if (p.retrieving && p.captured && p.tool < tips_.size()) {
      state = ClotState::kDragged;
      shift = tips_[p.tool] - p.retrieval_tip_mm;
    }
  }
  const double mid_mm = c.arc_start_mm + 0.5 * c.length_mm;
  return {glm::vec3(locator_.point_at(c.segment, c.arc_start_mm) + shift),
          glm::vec3(locator_.point_at(c.segment, c.arc_start_mm + c.length_mm) + shift),
          static_cast<float>(locator_.radius_at(c.segment, mid_mm)), state};
}

}  // namespace cathbox::session
