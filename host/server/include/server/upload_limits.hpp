#pragma once
// The bounds an uploaded case or record must keep before the server does the expensive work
// (meshing the vessel, replaying the run), so one upload cannot take the memory or the CPU of the
// whole centre. Each is checked on the upload's own text or header first; a refusal is one line
// naming the file, what it has and the limit (413). The defaults are in docs/security.md.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "server/result.hpp"

namespace cathbox::server {

struct UploadLimits {
  // The vessel (HCLM): centreline points, checked on the parsed text; surface triangles, counted
  // on the control mesh before it is subdivided (what the subdivision will make of it).
  std::int64_t max_vessel_points = 20'000;
  std::int64_t max_surface_triangles = 1'500'000;
  // The record: its simulated time (ticks x tick period), counted by reading its ticks before the
  // replay; and the replay's CPU time, checked every 1,000 ticks while it runs.
  std::int64_t max_record_duration_s = 2 * 3600;
  double max_replay_cpu_s = 900.0;
  // The replay's CPU clock in seconds (default: the calling thread's CPU time); tests inject one.
  std::function<double()> cpu_seconds;
};

// The calling thread's CPU time in seconds.
[[nodiscard]] double thread_cpu_seconds();

// Checks an HCLM text against the vessel bounds (the surface meshed at `subdivision_level` with
// `ring_points` a ring, the trainer's level 2 and 8 by default) without meshing it. An HCLM the
// reader refuses passes here: its own reader's line comes from the caller's next step.
[[nodiscard]] Status check_vessel_bounds(std::string_view hclm_text, const std::string& file, const UploadLimits& limits,
                                         int subdivision_level = 2, int ring_points = 8);

}  // namespace cathbox::server
