#pragma once
// Time-stamped actions for the headless scenario runner (documented in sim/tool/README.md):
//
//   # time_ms  verb       arguments
//   0          select     guidewire          # the tool the next actions move (by name)
//   0          insert_to  120 at 20          # mm, optional speed in mm/s (default 20)
//   1500       rotate_by  90 at 180          # degrees, optional speed in deg/s (default 180)
//   4000       insert_by  -5
//   6000       end                           # optional: stop here
//   # imaging (the session and the trainer act on these; `cathbox sim run` skips them)
//   2000       fluoro     on                 # fluoroscopy pedal down (off: up)
//   2500       inject     6 at 3             # mL of contrast at mL/s from the selected catheter's tip
//   2600       inject     4 at 2 conc 240    # ... of 240 mgI/mL (default: the session's, 300)
//   5000       carm       -20 15             # C-arm to LAO (+) / RAO (-) and cranial (+) / caudal (-) degrees
//   5200       roadmap                       # the last run's peak frame as roadmap (off: remove it)
//   # devices (the selected tool)
//   7000       inflate    6 atm                # balloon: the inflation device to 6 atm (or `0.4 ml`)
//   12000      deflate                       # balloon: vacuum
//   13000      detach                        # coil: release the selected coil tool's coil
//   13100      load_coil                     # coil: withdraw the released coil's pusher and feed
//                                            # the tool's next coil (the case's next_coil) at the hub
//   # thrombectomy (the session acts on these; `cathbox sim run` skips them)
//   14000      aspiration on                 # the selected catheter's vacuum on (off: off)
//   14000      balloon_guide inflate         # the selected guide's balloon: flow arrest (deflate)
//
// Times are milliseconds of virtual time, non-decreasing. A motion moves the value towards
// its target at the given speed; a new motion of the same tool and axis replaces the old one.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/result.hpp"

namespace cathbox::tool {

enum class ActionKind : std::uint8_t {
  kSelect, kInsertTo, kInsertBy, kRotateTo, kRotateBy, kEnd,
  kFluoro,   // value 1: pedal down, 0: up
  kInject,   // value mL, speed mL/s
  kCArm,     // value LAO degrees, value2 cranial degrees
  kRoadmap,  // value 1: capture, 0: remove
  kDetach,   // release the selected tool's coil
  kInflatePressure,  // value atm, the selected tool's balloon
  kInflateVolume,    // value mL
  kDeflate,
  kLoadCoil,  // the selected coil tool's next coil, on a new pusher at the hub (insertion 0)
  kAspiration,   // value 1: the selected catheter's vacuum on, 0: off
  kBalloonGuide, // value 1: the selected guide's balloon inflated (flow arrest), 0: deflated
};

// True for the thrombectomy verbs (aspiration, balloon_guide).
[[nodiscard]] constexpr bool is_thrombectomy(ActionKind k) { return k == ActionKind::kAspiration || k == ActionKind::kBalloonGuide; }

// True for the balloon verbs (inflate, deflate).
[[nodiscard]] constexpr bool is_balloon(ActionKind k) {
  return k == ActionKind::kInflatePressure || k == ActionKind::kInflateVolume || k == ActionKind::kDeflate;
}

// True for the imaging verbs (fluoro, inject, carm, roadmap).
[[nodiscard]] constexpr bool is_imaging(ActionKind k) {
  return k == ActionKind::kFluoro || k == ActionKind::kInject || k == ActionKind::kCArm || k == ActionKind::kRoadmap;
}

struct Action {
  std::int64_t time_ms = 0;
  ActionKind kind = ActionKind::kEnd;
  double value = 0.0;   // mm or degrees; fluoro/roadmap 1 or 0; inject mL; carm LAO degrees
  double speed = 0.0;   // mm/s or deg/s; inject mL/s
  double value2 = 0.0;  // carm cranial degrees
  double concentration_mgI_ml = 0.0;  // inject `conc`; 0: not given (the session's default)
  std::string tool;     // kSelect
  std::size_t line = 0; // source line, for errors found later
};

struct Script {
  std::vector<Action> actions;
};

// The script, or one line "file:line: message".
using ScriptParse = base::Result<Script>;

[[nodiscard]] ScriptParse parse_script(std::string_view text, std::string_view file_name);
[[nodiscard]] ScriptParse load_script(const std::string& path);

inline constexpr double kDefaultInsertSpeed_mm_s = 20.0;
inline constexpr double kDefaultRotateSpeed_deg_s = 180.0;
inline constexpr double kDefaultInjectRate_ml_s = 3.0;
inline constexpr double kMaxInjectConcentration_mgI_ml = 1000.0;  // flow::ContrastTransport's limit
inline constexpr double kMaxInflate_atm = 30.0;  // Balloon::kMaxPressure_atm
inline constexpr double kMaxInflate_ml = 20.0;

}  // namespace cathbox::tool
