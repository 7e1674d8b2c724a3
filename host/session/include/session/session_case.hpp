#pragma once
// A case as a session runs it, loaded the one way every front end loads it: a case file
// through tool::load_case, or a bare HCLM file with the default guidewire from the start of the
// root segment, then tool::build_world (the wall, the entry, the target, the surface). Keeps
// the files' bytes verbatim for the record, and what the session derives from the vessel: the
// centreline route from the entry to the target (metrics, autopilot), the target's radius,
// the blood flow over the vessel network (the fluoroscopy unit's contrast).
// A record rebuilds the same case from its header (the HCLM it carries, the tools and the
// entry it recorded), whatever the files on disk hold now.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "base/result.hpp"
#include "flow/flow_network.hpp"
#include "session/centerline_path.hpp"
#include "session/record_header.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"

namespace cathbox::session {

struct SessionCase {
  std::string name;         // the case's name, else its file name
  std::string case_file;    // as opened; empty for a bare vessel file
  std::string case_text;    // its bytes
  std::string vessel_file;  // the HCLM file; empty for analytic tubes
  std::string vessel_text;  // its bytes
  std::string surface_file;   // the case's own wall (`surface FILE`); empty: meshed from the HCLM
  std::string surface_bytes;  // its bytes (CBXMESH2)
  tool::Case spec;          // tools, target, entry as the case gives them
  std::unique_ptr<tool::CaseWorld> world;
  tool::Entry entry;        // where the tools enter (the case's, else the default)

  // From the vessel (empty for analytic tubes).
  std::unique_ptr<flow::FlowNetwork> flow;  // the steady blood flow (sim/flow), solved at load
  std::string flow_error;                   // why a bare vessel file has none (no fluoroscopy)
  std::vector<PathSegment> segments;        // the centreline graph
  std::vector<glm::vec3> route_mm;          // entry -> target (or the farthest leaf)
  std::vector<std::int32_t> route_segment_ids;  // segment ids along route_mm (with a target)
  double route_length_mm = -1.0;            // with a target
  std::optional<glm::vec3> target_mm;
  float target_radius_mm = 2.0F;
  double wall_force_threshold_mN = 100.0;

  [[nodiscard]] const vessel::SurfaceMesh* mesh() const { return world ? world->mesh() : nullptr; }
  [[nodiscard]] const vessel::VesselModel* model() const { return world ? world->model() : nullptr; }
  // The wall is the case's own surface (`surface FILE`): views show it as it is, not re-meshed.
  [[nodiscard]] bool surface_given() const { return world && world->surface_given(); }
  // The first vessel wall point along a ray (the collision tree's ray cast): picking in a
  // view. Thread-safe (the tree is immutable).
  [[nodiscard]] std::optional<glm::vec3> pick(const glm::vec3& origin_mm, const glm::vec3& direction) const;
};

// A case ready to run, or one line naming the file ("file:line: message").
using SessionCaseLoad = base::Result<std::unique_ptr<SessionCase>>;

// A .case file, or a bare .hclm vessel file. `surface`: the vessel surface made elsewhere
// (vessel/mesh_wire.hpp) instead of meshed here, for a build without OpenSubdiv (WebAssembly);
// it must be the one this vessel meshes to, or the run is another run.
[[nodiscard]] SessionCaseLoad load_session_case(const std::string& path, const vessel::SurfaceMesh* surface = nullptr);
// The case a record was made on, from its header.
[[nodiscard]] SessionCaseLoad session_case_from_record(const RecordHeader& header,
                                                       const vessel::SurfaceMesh* surface = nullptr);

}  // namespace cathbox::session
