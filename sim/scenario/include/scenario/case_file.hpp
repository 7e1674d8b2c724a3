#pragma once
// A case: the vessel (an HCLM file, or analytic tubes), the entry point and direction, the
// target (segment and position along it) and the tools. Text format, one statement a line
// (documented in sim/tool/README.md):
//
//   cathbox-case 1
//   name   carotid-demo
//   vessel neuro.hclm                       # path relative to the case file
//   surface lumen.cbxmesh                   # optional: the vessel's wall as a surface (CBXMESH2,
//                                           # `cathbox vessel import --surface-out`) instead of
//                                           # the mesh made from the HCLM, which still gives the
//                                           # centreline graph (route, targets, flow, entry)
//   tube   SEG  X0 Y0 Z0 R0  X1 Y1 Z1 R1     # analytic lumen piece instead of a vessel file
//   entry  X Y Z  DX DY DZ                  # optional: default is the start of the root segment
//   target SEG FRACTION                     # fraction of the segment's length, 0..1
//   wall_force_threshold MN                 # optional: the session's "time above" wall force
//   valve_friction MN                       # optional: haemostatic valve friction of every tool
//                                           # (default 20 mN; a tool's own line overrides it)
//   aneurysm DX DY DZ R  NX NY NZ            # optional: the sac as a dome sphere (centre, radius)
//                                           # cut at its neck centre (default: found in the vessel)
//   tool   NAME guidewire|catheter|coil
//     section LENGTH od=MM ei=N.mm2 gj=N.mm2 [curve=DEG] [shape=helix|complex loop=MM]
//                                           # proximal first; shape/loop: a coil's secondary shape
//     friction MU
//     inner_diameter MM                     # catheters
//     inside NAME                           # coaxial: the catheter this tool runs in (any depth)
//     detach MM                             # coils: the detachable coil's length at the tip
//     next_coil LENGTH od=MM ei=N.mm2 gj=N.mm2 shape=helix|complex loop=MM
//                                           # coils: the next coils (load_coil), in order, <= 15
//     spacing MAX_MM TIP_MM [TIP_ZONE_MM]
//     drag MN_S_PER_MM2                     # default: blood's (flow viscosity), from physics
//     valve_friction MN
//     axial_stiffness N
//     balloon length=MM from_tip=MM nominal=ATM burst=ATM chart=P:D,P:D,...   # catheters
//     stent_retriever diameter=MM length=MM [embed=S]   # a push wire (guidewire tool) inside the
//                                           # catheter delivering it: 3-6 x 20-40 mm, embedding
//                                           # time (0, 1800] s, default 180 (tool/stent_retriever.hpp)
//   end
//   flow   KEY VALUES...                    # blood flow overrides (sim/flow), see the README:
//          viscosity MPA_S | cardiac_output ML_PER_MIN | cerebral_fraction F |
//          pressure ARTERIAL_MMHG VENOUS_MMHG | wall_shear_stress PA | dispersion RADII |
//          pulsatile BPM PI | terminals calibrated|fixed | inflow SEG ML_PER_MIN | outlet SEG ML_PER_MIN |
//          closed SEG [EXCHANGE_FRACTION]
//   view   NAME LAO_DEG CRANIAL_DEG          # a working projection of the C-arm (RAO/caudal negative)
//   realistic                               # fluoroscopy only: no 3D view for the trainee
//   wall   cervical|intracranial RADIUS_MM  # optional: a compliant wall (compliant_contact.hpp)
//   clot   SEG FROM_MM LENGTH_MM [red=PCT] [fibrin=PCT] [open=F]
//                                           # a thrombus in segment SEG from FROM_MM along it
//                                           # (flow/clot.hpp); default 45 % / 45 %, open 0
//   (in a catheter) aspiration pump|syringe # an aspiration catheter's vacuum source
//
// Bad input gives one line "file:line: message"; parsing never throws or crashes.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/result.hpp"
#include "flow/aspiration.hpp"
#include "flow/c_arm.hpp"
#include "flow/clot_material.hpp"
#include "flow/flow_settings.hpp"
#include "tool/aneurysm_sac.hpp"
#include "tool/arterial_wall.hpp"
#include "tool/simulator.hpp"
#include "tool/tool_spec.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::tool {

struct CaseTarget {
  std::int32_t segment = -1;
  double fraction = 1.0;
};

// `wall TERRITORY [RADIUS_MM]`: the wall gives under the tools by its own mechanics
// (compliant_contact.hpp), with the territory's material (arterial_wall.hpp) at that lumen radius
// (without one, a `vessel`'s: its centreline graph's median radius, the distance to the surface
// for an imported one), and distends with the pulse (wall_distension.hpp), a meshed vessel's or
// a `surface`'s alike.
struct CaseWall {
  Territory territory = Territory::kCervical;
  double radius_mm = 2.0;  // 0: the vessel's
};

// `clot SEG FROM_MM LENGTH_MM ...`: the segment is checked against the vessel model when the
// case is resolved (case_clots.hpp), naming `line`.
struct CaseClot {
  std::int32_t segment_id = 0;
  double from_mm = 0.0;
  double length_mm = 0.0;
  flow::ClotComposition composition;
  double open_fraction = 0.0;
  std::size_t line = 0;
  friend bool operator==(const CaseClot&, const CaseClot&) = default;
};

// `aspiration pump|syringe` in a catheter: the catheter aspirates through its inner diameter.
struct CaseAspiration {
  std::string tool;
  flow::VacuumSource source = flow::VacuumSource::kPump;
  std::size_t line = 0;
};

struct Case {
  std::string name;
  std::string vessel_path;       // resolved against the case file's folder; empty: analytic tubes
  std::string surface_path;      // `surface FILE`, resolved likewise; empty: the wall is meshed from the HCLM
  std::vector<Tube> tubes;
  std::optional<Entry> entry;
  std::optional<CaseTarget> target;
  std::optional<double> wall_force_threshold_mN;  // for the session's metrics (default there: 100 mN)
  std::optional<double> valve_friction_mN;        // every tool's valve unless it names its own
  std::vector<ToolSpec> tools;   // the defaults (a guidewire) when the file names none
  flow::FlowSettings flow;       // physiological defaults plus the file's `flow` overrides
  std::vector<flow::NamedProjection> views;  // the case's working projections (besides AP, lateral)
  bool realistic = false;        // the 3D view is off for the trainee (fluoroscopy only)
  // `aneurysm`: a declared sac (sphere cap); without it the world looks for one in the vessel.
  std::optional<AneurysmSac> aneurysm;
  std::optional<CaseWall> wall;  // none: the rigid wall (contact by the solver's penalty)
  std::vector<CaseClot> clots;   // at most 16
  std::vector<CaseAspiration> aspiration;  // one per aspirating catheter
};

// The case, or one line "file:line: message".
using CaseParse = base::Result<Case>;

// Parses case text; `file_name` names the source in errors and anchors relative paths.
[[nodiscard]] CaseParse parse_case(std::string_view text, std::string_view file_name);
// Reads and parses a case file.
[[nodiscard]] CaseParse load_case(const std::string& path);
// Marks each catheter the case aspirates through steered by the tools it carries while its hand
// advances it (`InnerSteering::kWhileAdvanced`: tracked over them to the clot), the others not
// (a balloon catheter's kAlways is the Simulator's). parse_case
// does it; a caller that replaces `c.tools` (a record's tools) does it again.
void steer_aspiration_catheters(Case& c);

// A 0.014" guidewire with a soft distal tip and an angled tip, and a 5F catheter.
[[nodiscard]] ToolSpec default_guidewire();
[[nodiscard]] ToolSpec default_catheter();
// A microcatheter with a 0.45 mm (0.018") lumen, and a 10-system detachable coil (0.25 mm
// primary wind of EI 0.02 N.mm2, helical secondary shape of `loop_diameter_mm`) of
// `length_mm` on a 0.33 mm pusher, running in the microcatheter ("microcatheter"), its nodes
// 0.5 mm apart over the coil.
[[nodiscard]] ToolSpec default_microcatheter();
[[nodiscard]] ToolSpec default_coil(double length_mm, double loop_diameter_mm);

}  // namespace cathbox::tool
