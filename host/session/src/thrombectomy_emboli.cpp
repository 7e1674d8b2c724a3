// The thrombectomy unit's emboli (thrombectomy_unit.hpp): fragments released into the flow,
// carried tick by tick in virtual time with the network's flows of the moment, lodged where
// they no longer fit, then clots like the others (occluding, graded, drawn, retrievable).
#include <algorithm>

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
    if (in_transit_.back().done()) lodge(time_us, in_transit_.back());
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
    lodge(time_us, e);
    lodged = true;
  }
  if (lodged) std::erase_if(in_transit_, [](const flow::EmbolusTransit& e) { return e.done(); });
}

// The embolus as a clot where it stopped: the control run with and without it (an ENT when it
// starves an outlet outside the target territory), the pass graded again, any arrest restored.
// Allocates and re-solves: an event.
void ThrombectomyUnit::lodge(std::int64_t time_us, const flow::EmbolusTransit& transit) {
  if (!resolve(time_us, false)) return;
  const std::vector<flow::Terminal> without = network_.terminals();
  const flow::Clot& embolus = transit.path().lodged;
  clots_.push_back(embolus);
  if (!resolve(time_us, false)) return;
  const bool ent = !flow::new_territories(target_, without, network_.terminals()).empty();
  ++figures_.emboli;
  if (ent) ++figures_.emboli_new_territory;
  figures_.emboli_lodged.push_back(segment_name(embolus.segment));
  regrade(time_us);
  log(time_us, "embolus lodged in the %s (%.0f ms, %.0f mm)%s: eTICI %s", segment_name(embolus.segment).c_str(),
      1e3 * transit.elapsed_s(), transit.travelled_mm(), ent ? " (ENT)" : "",
      std::string(flow::etici_label(figures_.etici_final)).c_str());
  if (!arrests_.empty()) (void)resolve(time_us, true);
}

}  // namespace cathbox::session
