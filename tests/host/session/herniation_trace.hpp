#pragma once
// Where and when coil crosses the neck plane in a coiling session: an observer that, on every
// tick with herniated coil (the rule of tool::CoilMetrics: a deployed node past the neck plane by
// more than its radius, the last 1 mm leaving the catheter excepted), notes which coil (the coil
// tool's attached one, or the n-th released), which of its nodes (from its distal tip), how deep
// and how far off the sac's axis, and where the microcatheter's tip is; it prints each episode's
// onset and its largest tick. The dense coiling run prints it (dense_coiling_test.cpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "session/session.hpp"
#include "tool/aneurysm_sac.hpp"

namespace cathbox::session::test {

class HerniationTrace : public TickObserver {
 public:
  explicit HerniationTrace(const tool::AneurysmSac& sac) : sac_(sac) {}

  struct Crossing {
    double time_s = 0.0;
    std::string coil;            // "coil 2 attached (41.3 mm out)" or "coil 1 released"
    int nodes = 0;               // of this coil, past the plane
    double first_mm = 0.0;       // the crossing nodes' span along the coil, from its distal tip
    double last_mm = 0.0;
    double deepest_mm = 0.0;     // past the neck plane
    double off_axis_mm = 0.0;    // the deepest node's distance from the sac's axis
    double catheter_depth_mm = 0.0;   // the microcatheter's tip: past the neck plane (+: in the sac)
    double catheter_off_axis_mm = 0.0;
  };
  struct Episode {
    std::vector<Crossing> onset;  // the first tick's crossings
    std::vector<Crossing> peak;   // the tick with the most herniated nodes
    int peak_nodes = 0;
    double end_s = 0.0;
  };
  std::vector<Episode> episodes;
  // Per second of deployment: the shallowest deployed coil node's side of the plane (its depth
  // less its radius: below 0 part of it is past the plane, below -2 radii it counts) and the
  // microcatheter tip's range of depth past the neck plane.
  struct Window {
    double time_s = 0.0;
    double coil_margin_mm = 1e9;
    std::string coil;
    double catheter_min_mm = 1e9;
    double catheter_max_mm = -1e9;
  };
  std::vector<Window> timeline;

  void observe(const TickView& v) override {
    const tool::Simulator& sim = v.sim;
    const double t = static_cast<double>(v.time_us) * 1e-6;
    std::vector<Crossing> now;
    for (std::size_t tool = 0; tool < sim.tool_count(); ++tool) {
      const tool::Rod& rod = sim.rod(tool);
      if (rod.spec().kind != tool::ToolKind::kCoil || rod.spec().detach_mm <= 0.0 || sim.released_mm(tool) > 0.0) continue;
      const double out = std::clamp(sim.tip_depth_mm(tool) - sim.free_start_mm(tool), 0.0, rod.spec().detach_mm);
      if (out <= 0.0) continue;
      char name[64];
      std::snprintf(name, sizeof name, "coil %zu attached (%.1f mm out)", sim.coils_loaded(tool), out);
      scan(sim, rod, rod.first_free_node(), rod.node_total(), out - 1.0, name, sim.outer_of(tool), t, now);
    }
    for (std::size_t i = 0; i < sim.detached_count(); ++i) {
      const tool::Rod& coil = sim.detached(i);
      char name[48];
      std::snprintf(name, sizeof name, "coil %zu released", i + 1);
      scan(sim, coil, 0, coil.node_total(), coil.length_mm() + 1.0, name, catheter_, t, now);
    }
    if (v.time_us / 1000000 != window_start_s_) {  // a second's window closed
      if (window_.coil_margin_mm < 1e8) timeline.push_back(window_);
      window_ = Window{};
      window_start_s_ = v.time_us / 1000000;
      window_.time_s = static_cast<double>(window_start_s_);
    }
    int total = 0;
    for (const Crossing& c : now) total += c.nodes;
    if (total == 0) {
      in_episode_ = false;
      return;
    }
    if (!in_episode_ && (episodes.empty() || t - episodes.back().end_s >= 0.5)) episodes.push_back(Episode{now, now, total, t});
    in_episode_ = true;
    Episode& e = episodes.back();
    e.end_s = t;
    if (total > e.peak_nodes) {
      e.peak_nodes = total;
      e.peak = now;
    }
  }

  void print() const {
    std::printf("  from s: shallowest coil node (depth - radius, mm) / microcatheter tip past the neck (mm)\n");
    for (const Window& w : timeline) {
      std::printf("    %3.0f s  %+.2f (%s)  tip %.2f..%.2f\n", w.time_s, w.coil_margin_mm, w.coil.c_str(), w.catheter_min_mm,
                  w.catheter_max_mm);
    }
    std::printf("  herniation trace: %zu episodes\n", episodes.size());
    for (const Episode& e : episodes) {
      std::printf("  episode to %.3f s, up to %d nodes\n", e.end_s, e.peak_nodes);
      print_rows("onset", e.onset);
      print_rows("peak", e.peak);
    }
  }

 private:
  void scan(const tool::Simulator& sim, const tool::Rod& rod, std::size_t first, std::size_t end, double leaving_mm,
            const char* name, std::size_t catheter, double t, std::vector<Crossing>& out) {
    Crossing c;
    c.time_s = t;
    c.coil = name;
    c.first_mm = 1e9;
    const std::span<const glm::dvec3> x = rod.positions();
    for (std::size_t k = first; k < end; ++k) {
      if (rod.node_from_tip_mm(k) > leaving_mm) continue;
      const double depth = sac_.depth_mm(x[k]);
      if (depth - rod.node_radius_mm(k) < window_.coil_margin_mm) {
        window_.coil_margin_mm = depth - rod.node_radius_mm(k);
        window_.coil = name;
      }
      if (depth >= -rod.node_radius_mm(k)) continue;
      ++c.nodes;
      c.first_mm = std::min(c.first_mm, rod.node_from_tip_mm(k));
      c.last_mm = std::max(c.last_mm, rod.node_from_tip_mm(k));
      if (-depth > c.deepest_mm) {
        c.deepest_mm = -depth;
        c.off_axis_mm = off_axis(x[k]);
      }
    }
    if (catheter < sim.tool_count()) {
      catheter_ = catheter;
      const glm::dvec3 tip = sim.tip(catheter).position_mm;
      c.catheter_depth_mm = sac_.depth_mm(tip);
      c.catheter_off_axis_mm = off_axis(tip);
      window_.catheter_min_mm = std::min(window_.catheter_min_mm, c.catheter_depth_mm);
      window_.catheter_max_mm = std::max(window_.catheter_max_mm, c.catheter_depth_mm);
    }
    if (c.nodes > 0) out.push_back(c);
  }

  double off_axis(const glm::dvec3& p) const {
    const glm::dvec3 d = p - sac_.neck_centre_mm;
    return glm::length(d - glm::dot(d, sac_.neck_normal) * sac_.neck_normal);
  }

  static void print_rows(const char* what, const std::vector<Crossing>& rows) {
    for (const Crossing& c : rows) {
      std::printf("    %-5s %.3f s  %s: %d nodes, %.1f-%.1f mm from its tip, deepest %.2f mm past the neck (%.2f mm off "
                  "the axis); microcatheter tip %.2f mm past the neck, %.2f mm off the axis\n",
                  what, c.time_s, c.coil.c_str(), c.nodes, c.first_mm, c.last_mm, c.deepest_mm, c.off_axis_mm,
                  c.catheter_depth_mm, c.catheter_off_axis_mm);
    }
  }

  tool::AneurysmSac sac_;
  std::size_t catheter_ = static_cast<std::size_t>(-1);
  bool in_episode_ = false;
  Window window_;
  std::int64_t window_start_s_ = -1;
};

}  // namespace cathbox::session::test
