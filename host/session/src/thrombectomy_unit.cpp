#include "session/thrombectomy_unit.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <cstdarg>
#include <cstdio>

#include <glm/geometric.hpp>

#include "flow/embolus.hpp"
#include "session/event_log.hpp"

namespace cathbox::session {
namespace {

constexpr double kContiguous_mm = 1.0;  // clots this close across a junction are one thrombus

const char* outcome_text(flow::AspirationOutcome o) {
  return o == flow::AspirationOutcome::kIngested ? "ingested" : (o == flow::AspirationOutcome::kCorked ? "corked" : "lost");
}

}  // namespace

std::unique_ptr<ThrombectomyUnit> ThrombectomyUnit::make(flow::FlowNetwork& network, const tool::Case& spec,
                                                         EventLog& events, std::string& why_not) {
  if (network.clots().empty()) return nullptr;
  const std::vector<flow::Clot> clots = network.clots();
  const std::vector<flow::Terminal> occluded = network.terminals();
  if (base::Status<> open = network.occlude({}); !open) {
    why_not = open.error().message;
    return nullptr;
  }
  const std::vector<flow::Terminal> baseline = network.terminals();
  if (base::Status<> back = network.occlude(clots); !back) {
    why_not = back.error().message;
    return nullptr;
  }
  base::Result<flow::TargetTerritory> target = flow::TargetTerritory::find(baseline, occluded);
  if (!target) {
    why_not = target.error().message;
    return nullptr;
  }
  std::unique_ptr<ThrombectomyUnit> u(new ThrombectomyUnit(network, events, std::move(*target)));
  for (const flow::Clot& c : clots) u->add_clot(c);
  const std::size_t n = spec.tools.size();
  u->aspirating_.assign(n, 0);
  u->balloon_.assign(n, 0);
  for (std::size_t t = 0; t < n; ++t) {
    u->tool_names_.push_back(spec.tools[t].name);
    u->balloon_[t] = spec.tools[t].balloon.present() ? 1 : 0;
    u->inner_diameter_.push_back(spec.tools[t].inner_diameter_mm);
  }
  for (std::size_t t = 0; t < n; ++t) {
    if (!spec.tools[t].stent.present()) continue;
    StentPass p;
    p.tool = t;
    p.spec = spec.tools[t].stent;
    u->stents_.push_back(p);
  }
  for (const tool::CaseAspiration& a : spec.aspiration) {
    for (std::size_t t = 0; t < n; ++t) {
      if (spec.tools[t].name != a.tool) continue;
      double length_mm = 0.0;
      for (const tool::ToolSection& s : spec.tools[t].sections) length_mm += s.length_mm;
      u->aspirators_.push_back({t, a.source, spec.tools[t].inner_diameter_mm, length_mm});
    }
  }
  u->figures_.reperfused_pct_final = std::round(100.0 * u->target_.reperfused_fraction(occluded));
  u->figures_.etici_final = u->target_.grade(occluded);
  return u;
}

ThrombectomyUnit::ThrombectomyUnit(flow::FlowNetwork& network, EventLog& events, flow::TargetTerritory target)
    : network_(network), events_(events), target_(std::move(target)), locator_(network.model()) {}

void ThrombectomyUnit::log(std::int64_t time_us, const char* fmt, ...) {
  char buf[112];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  (void)events_.push(time_us, buf);
}

std::string ThrombectomyUnit::segment_name(std::uint32_t segment) const {
  const vessel::Segment& s = network_.model().segments[segment];
  return s.name.empty() ? "segment " + std::to_string(s.id) : s.name;
}

std::optional<std::size_t> ThrombectomyUnit::index_of(ClotId id) const {
  const auto k = std::find(clot_ids_.begin(), clot_ids_.end(), id);
  return k == clot_ids_.end() ? std::nullopt : std::optional<std::size_t>(static_cast<std::size_t>(k - clot_ids_.begin()));
}

bool ThrombectomyUnit::all_remain(const std::vector<ClotId>& ids) const {
  return std::all_of(ids.begin(), ids.end(), [this](ClotId id) { return index_of(id).has_value(); });
}

void ThrombectomyUnit::add_clot(const flow::Clot& c) {
  clots_.push_back(c);
  clot_ids_.push_back(next_clot_id_++);
}

void ThrombectomyUnit::erase_clots(std::span<const ClotId> ids) {
  for (const ClotId id : ids) {
    const std::optional<std::size_t> k = index_of(id);
    if (!k) continue;
    clots_.erase(clots_.begin() + static_cast<std::ptrdiff_t>(*k));
    clot_ids_.erase(clot_ids_.begin() + static_cast<std::ptrdiff_t>(*k));
  }
}

bool ThrombectomyUnit::resolve(std::int64_t time_us, bool live) {
  const std::span<const flow::FlowArrest> arrests = live ? std::span<const flow::FlowArrest>(arrests_) : std::span<const flow::FlowArrest>();
  const std::span<const flow::AspirationSink> sinks = live ? std::span<const flow::AspirationSink>(sinks_) : std::span<const flow::AspirationSink>();
  ++flow_generation_;
  if (base::Status<> s = network_.occlude(clots_, arrests, sinks); !s) {
    log(time_us, "flow: %s", s.error().message.c_str());
    return false;
  }
  return true;
}

std::vector<ClotId> ThrombectomyUnit::thrombus_of(std::size_t first) const {
  const vessel::VesselModel& model = network_.model();
  std::vector<std::size_t> group{first};
  // Clots touching across a junction: one ends at its segment's end, the next starts a child.
  for (std::size_t g = 0; g < group.size(); ++g) {
    const flow::Clot& a = clots_[group[g]];
    for (std::size_t j = 0; j < clots_.size(); ++j) {
      if (std::find(group.begin(), group.end(), j) != group.end()) continue;
      const flow::Clot& b = clots_[j];
      const auto touches = [&](const flow::Clot& up, const flow::Clot& down) {
        if (up.arc_start_mm + up.length_mm < locator_.length_mm(up.segment) - kContiguous_mm || down.arc_start_mm > kContiguous_mm) return false;
        for (const std::int32_t id : model.segments[up.segment].children) {
          if (model.index_of(id) == std::optional<std::size_t>(down.segment)) return true;
        }
        return false;
      };
      if (touches(a, b) || touches(b, a)) group.push_back(j);
    }
  }
  std::vector<ClotId> ids;
  for (const std::size_t k : group) ids.push_back(clot_ids_[k]);
  return ids;
}

std::optional<std::size_t> ThrombectomyUnit::clot_at_tip(const glm::dvec3& tip_mm) const {
  for (std::size_t k = 0; k < clots_.size(); ++k) {
    const flow::Clot& c = clots_[k];
    if (glm::distance(tip_mm, locator_.point_at(c.segment, c.arc_start_mm)) <= kFaceReach_mm) return k;
    const flow::CenterlinePosition on = locator_.nearest_on(c.segment, tip_mm);
    if (on.arc_mm >= c.arc_start_mm && on.arc_mm <= c.arc_start_mm + c.length_mm &&
        on.distance_mm <= locator_.radius_at(c.segment, on.arc_mm)) {
      return k;
    }
  }
  return std::nullopt;
}

void ThrombectomyUnit::tick(std::int64_t time_us, const tool::Snapshot& snapshot) {
  carry_emboli(time_us);
  const std::size_t n = std::min(snapshot.tools.size(), tool_names_.size());
  tips_.resize(n);
  for (std::size_t t = 0; t < n; ++t) tips_[t] = snapshot.tools[t].tip.position_mm;
  for (StentPass& p : stents_) {  // a dragged clot's path: the stent's distal nodes (no allocation)
    if (p.path.empty() || p.tool >= n) continue;
    const std::vector<glm::dvec3>& x = snapshot.tools[p.tool].positions_mm;
    const std::size_t m = std::min(p.path.size(), x.size());
    std::copy(x.end() - static_cast<std::ptrdiff_t>(m), x.end(), p.path.end() - static_cast<std::ptrdiff_t>(m));
  }
  if (arrest_since_us_ >= 0) figures_.flow_arrest_s = static_cast<double>(arrest_before_us_ + time_us - arrest_since_us_) * 1e-6;
  update_sinks(time_us);
  if (const std::optional<std::size_t> held = hold_.tool()) {
    if (hold_.withdrawn(snapshot.tools[*held].insertion_mm)) end_pass(time_us);
    return;
  }
  for (const Aspirator& a : aspirators_) {
    if (a.tool >= n || aspirating_[a.tool] == 0) continue;
    const std::optional<std::size_t> k = clot_at_tip(tips_[a.tool]);
    if (!k) continue;
    hold_.engage(a.tool, thrombus_of(*k), snapshot.tools[a.tool].insertion_mm);
    log(time_us, "aspiration: the %s's tip engages the clot in the %s", tool_names_[a.tool].c_str(),
        segment_name(clots_[*k].segment).c_str());
    return;
  }
}

double ThrombectomyUnit::head_Pa(const flow::Clot& c) const {
  const flow::SegmentFlow& seg = network_.segments()[c.segment];
  return network_.node_pressure_Pa(seg.start_node) - network_.node_pressure_Pa(seg.end_node);
}

flow::AspirationClot ThrombectomyUnit::thrombus_clot(const std::vector<ClotId>& group) const {
  const flow::Clot& face = clot_of(group.front());
  double length_mm = 0.0;
  for (const ClotId k : group) length_mm += clot_of(k).length_mm;
  return {2.0 * locator_.radius_at(face.segment, face.arc_start_mm), length_mm, face.composition};
}

void ThrombectomyUnit::end_pass(std::int64_t time_us) {
  const std::size_t tool = *hold_.tool();
  const Aspirator* a = aspirator(tool);
  const std::vector<ClotId> held = hold_.thrombus();
  const flow::AspirationClot clot = thrombus_clot(held);
  const flow::AspirationResult r = a->verdict(clot, head_Pa(clot_of(held.front())));
  const int pass = ++figures_.passes;
  log(time_us, "pass %d: the clot is %s (pull %.3f N, ingest %.3f N, hold %.3f N)", pass, outcome_text(r.outcome), r.force_N,
      r.ingest_force_N, r.hold_force_N);
  std::vector<flow::Fragment> fragments;
  std::vector<ClotId> removed;
  hold_.release();  // the tip is open again: it draws blood (mouth: its sink's node)
  if (r.outcome == flow::AspirationOutcome::kLost) {
    // A fragment the width of the lumen strips off the catheter's mouth where the tip is now,
    // into the flow there: the catheter's own sink draws it in when it out-draws every branch
    // at its node (under flow arrest, or with a strong vacuum), else the flow carries it away.
    fragments.push_back({mouth(tool), std::min(a->inner_diameter_mm, clot.diameter_mm), std::min(a->inner_diameter_mm, clot.length_mm),
                         clot.composition});
  } else {
    removed = held;
  }
  grade_pass(time_us, removed, fragments);
}

void ThrombectomyUnit::grade_pass(std::int64_t time_us, const std::vector<ClotId>& removed, const std::vector<flow::Fragment>& fragments) {
  erase_clots(removed);
  clots_removed_ += static_cast<int>(removed.size());
  // A vacuum held on a thrombus another device took out (a stent pulled into the engaged
  // catheter) holds nothing now: the tip is open (its sink draws again).
  if (const std::optional<std::size_t> held = hold_.tool(); hold_.release_removed(removed)) {
    log(time_us, "aspiration: the %s's tip holds no clot now (it left in pass %d)", tool_names_[*held].c_str(), figures_.passes);
  }
  pass_end_us_ = time_us;
  // The control run: the network without the arrest.
  if (!resolve(time_us, false)) return;
  regrade(time_us);
  const flow::Etici grade = figures_.etici_final;
  log(time_us, "pass %d: eTICI %s (%.0f %% reperfused)", figures_.passes, std::string(flow::etici_label(grade)).c_str(),
      figures_.reperfused_pct_final);
  sinks_ = live_sinks();
  (void)resolve(time_us, true);
  release(time_us, fragments);
}

void ThrombectomyUnit::regrade(std::int64_t time_us) {
  const int pass = figures_.passes;
  const double pct = std::round(100.0 * target_.reperfused_fraction(network_.terminals()));
  const flow::Etici grade = target_.grade(network_.terminals());
  const auto i = static_cast<std::size_t>(pass - 1);
  if (i < ThrombectomyFigures::kMaxPasses) {
    figures_.etici_after_pass[i] = grade;
    figures_.reperfused_pct_after_pass[i] = pct;
  }
  figures_.etici_final = grade;
  figures_.reperfused_pct_final = pct;
  if (pass == 1) figures_.first_pass_effect = flow::at_least(grade, flow::Etici::k2c);
  const bool reperfused = flow::at_least(grade, flow::Etici::k2b50);
  if (figures_.time_to_reperfusion_us < 0 && reperfused) figures_.time_to_reperfusion_us = time_us;
  // An embolus of the same pass undoes a reperfusion it reached.
  if (!reperfused && figures_.time_to_reperfusion_us == pass_end_us_) figures_.time_to_reperfusion_us = -1;
}

}  // namespace cathbox::session
