// The thrombectomy unit's emboli (thrombectomy_unit.hpp): fragments released into the flow,
// carried tick by tick in virtual time with the network's flows of the moment, lodged where
// they no longer fit, then clots like the others (occluding, graded, drawn, retrievable).
#include <algorithm>
#include <limits>

#include "flow/embolus.hpp"
#include "session/thrombectomy_unit.hpp"

namespace cathbox::session {

void ThrombectomyUnit::release(std::int64_t time_us, const std::vector<flow::Fragment>& fragments) {
  for (const flow::Fragment& f : fragments) {
    base::Result<flow::EmbolusTransit> t = flow::EmbolusTransit::start(network_, f);
    if (!t) {
      log(time_us, "%s", t.error().message.c_str());
      continue;
    }
    log(time_us, "a %.2f x %.1f mm fragment goes with the flow from the %s", f.diameter_mm, f.length_mm,
        segment_name(f.from.segment).c_str());
    in_transit_.push_back(std::move(*t));
    if (in_transit_.back().done()) settle(time_us, in_transit_.back());
  }
  std::erase_if(in_transit_, [](const flow::EmbolusTransit& e) { return e.done(); });
}

void ThrombectomyUnit::carry_emboli(std::int64_t time_us) {
  const double dt_s = last_tick_us_ >= 0 ? static_cast<double>(time_us - last_tick_us_) * 1e-6 : 0.0;
  last_tick_us_ = time_us;
  if (in_transit_.empty() || dt_s <= 0.0) return;
  bool lodged = false;
  for (flow::EmbolusTransit& e : in_transit_) {
    e.advance(network_, dt_s);
    if (!e.done()) continue;
    settle(time_us, e);
    lodged = true;
  }
  if (lodged) std::erase_if(in_transit_, [](const flow::EmbolusTransit& e) { return e.done(); });
}

// A fragment at the end of its transit: into an aspiration catheter (nothing to count), or lodged.
void ThrombectomyUnit::settle(std::int64_t time_us, const flow::EmbolusTransit& transit) {
  if (transit.state() != flow::TransitState::kAspirated) {
    lodge(time_us, transit);
    return;
  }
  log(time_us, "the aspiration catheter draws the fragment in (%.0f ms, %.0f mm)", 1e3 * transit.elapsed_s(), transit.travelled_mm());
}

// The embolus as a clot where it stopped: the control run with and without it (an ENT when it
// starves an outlet outside the target territory), the pass graded again, any arrest restored.
// Allocates and re-solves: an event.
void ThrombectomyUnit::lodge(std::int64_t time_us, const flow::EmbolusTransit& transit) {
  if (!resolve(time_us, false)) return;
  const std::vector<flow::Terminal> without = network_.terminals();
  const flow::Clot& embolus = transit.path().lodged;
  add_clot(embolus);
  if (!resolve(time_us, false)) return;
  const bool ent = !flow::new_territories(target_, without, network_.terminals()).empty();
  ++figures_.emboli;
  if (ent) ++figures_.emboli_new_territory;
  figures_.emboli_lodged.push_back(segment_name(embolus.segment));
  regrade(time_us);
  log(time_us, "embolus lodged in the %s (%.0f ms, %.0f mm)%s: eTICI %s", segment_name(embolus.segment).c_str(),
      1e3 * transit.elapsed_s(), transit.travelled_mm(), ent ? " (ENT)" : "",
      std::string(flow::etici_label(figures_.etici_final)).c_str());
  if (!arrests_.empty() || !sinks_.empty()) (void)resolve(time_us, true);
}

ClotView ThrombectomyUnit::embolus_view(std::size_t k) const {
  const flow::EmbolusTransit& e = in_transit_[k];
  const flow::CenterlinePosition at = e.position();
  const double length = locator_.length_mm(at.segment);
  // Behind its leading point: upstream, the segment's start when it flows forwards.
  const bool forwards = network_.segments()[at.segment].flow_mm3_s >= 0.0;
  const double lead = std::clamp(at.arc_mm, 0.0, length);
  const double tail = std::clamp(forwards ? lead - e.fragment().length_mm : lead + e.fragment().length_mm, 0.0, length);
  ClotView v;
  v.state = ClotState::kInTransit;
  v.radius_mm = static_cast<float>(0.5 * e.fragment().diameter_mm);
  for (int i = 0; i < ClotView::kAxisPoints; ++i) {
    const double f = static_cast<double>(i) / (ClotView::kAxisPoints - 1);
    v.axis_mm[static_cast<std::size_t>(i)] = glm::vec3(locator_.point_at(at.segment, tail + f * (lead - tail)));
  }
  v.start_mm = v.axis_mm.front();
  v.end_mm = v.axis_mm.back();
  return v;
}

// Each embolus still on its way, carried on to its end in the control run's network (no
// arrest); the ones before it lodged there too (clots with ids of their own, taken out again by
// those ids), so a later one meets the flows they leave.
void ThrombectomyUnit::finish(std::int64_t time_us) {
  if (finished_) return;
  finished_ = true;
  if (in_transit_.empty()) return;
  std::vector<ClotId> would_lodge;
  if (resolve(time_us, false)) {
    for (const flow::EmbolusTransit& e : in_transit_) {
      EmbolusInTransit d{segment_name(e.position().segment), e.position().arc_mm, {}, false};
      flow::EmbolusTransit on = e;
      on.advance(network_, std::numeric_limits<double>::infinity());
      if (on.state() == flow::TransitState::kAspirated) continue;  // the catheter would take it: not an embolus
      if (on.done()) {
        const std::vector<flow::Terminal> without = network_.terminals();
        add_clot(on.path().lodged);
        would_lodge.push_back(clot_ids_.back());
        if (!resolve(time_us, false)) break;
        d.would_lodge = segment_name(on.path().lodged.segment);
        d.new_territory = !flow::new_territories(target_, without, network_.terminals()).empty();
      }
      ++figures_.emboli;
      if (d.new_territory) ++figures_.emboli_new_territory;
      log(time_us, "embolus in transit in the %s at %.0f mm: %s%s%s", d.at.c_str(), d.at_mm,
          d.would_lodge.empty() ? "no flow carries it" : "would lodge in the ", d.would_lodge.c_str(), d.new_territory ? " (ENT)" : "");
      figures_.emboli_in_transit.push_back(std::move(d));
    }
  }
  erase_clots(would_lodge);
  (void)resolve(time_us, true);
}

}  // namespace cathbox::session
