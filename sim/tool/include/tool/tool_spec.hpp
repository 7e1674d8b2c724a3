#pragma once
// What a tool is made of: sections along its length (proximal to distal), each with an outer
// diameter, bending and torsional stiffness, an optional pre-curve (J-tip, angled tip) or a
// secondary coil shape, plus the wall friction and the node spacing of its discretisation.
// Catheters have a lumen (the next tool runs in it); a coil is a pusher wire carrying a
// detachable platinum coil at its distal end; a balloon catheter carries a balloon.
#include <cstdint>
#include <span>
#include <optional>
#include <string>
#include <vector>

namespace cathbox::tool {

enum class ToolKind : std::uint8_t { kGuidewire = 0, kCatheter = 1, kCoil = 2, kBalloon = 3 };

// A tube: a catheter or a balloon catheter (guides, aspiration catheters, microcatheters).
constexpr bool is_catheter(ToolKind kind) { return kind == ToolKind::kCatheter || kind == ToolKind::kBalloon; }

// Secondary (rest) shape of a coil section. The primary wind (the platinum wire wound into a
// soft spring of the section's outer diameter) is the section's od, ei and gj; the secondary
// shape is its rest curvature, taken up as the coil leaves the microcatheter:
//   kHelix: a helix of loop diameter D whose turns lie side by side (pitch = od);
//   kComplex: circular loops of diameter D, each in a plane turned 120 degrees about the
//             tangent from the last (a "3D" framing coil that builds a cage).
enum class CoilShape : std::uint8_t { kNone = 0, kHelix = 1, kComplex = 2 };

struct ToolSection {
  double length_mm = 0.0;
  double outer_diameter_mm = 0.36;
  double bending_stiffness_Nmm2 = 40.0;    // EI
  double torsion_stiffness_Nmm2 = 30.0;    // GJ
  double curve_deg = 0.0;                  // pre-curve: total bend of this section at rest
  CoilShape shape = CoilShape::kNone;      // coil sections: secondary shape
  double loop_diameter_mm = 0.0;           // ... and its loop diameter (2..20 mm)
};

// A balloon on a catheter: where it sits, and its compliance chart (diameter at each
// pressure, as manufacturers print it), nominal and rated-burst pressure.
struct BalloonSpec {
  double length_mm = 0.0;                  // working length; 0: no balloon
  double from_tip_mm = 0.0;                // distal end of the balloon from the catheter tip
  std::vector<double> pressure_atm;        // compliance chart, increasing pressures ...
  std::vector<double> diameter_mm;         // ... and the diameter at each
  double nominal_atm = 6.0;
  double rated_burst_atm = 14.0;
  [[nodiscard]] bool present() const { return length_mm > 0.0; }
};

// A stent retriever at a push wire's tip (stent_retriever.hpp): a self-expanding laser-cut
// nitinol stent of `diameter_mm` (unconstrained) over the distal `length_mm` of the wire,
// crimped in the microcatheter it is delivered through and expanding where it leaves it; it
// integrates a clot over `embed_s` (the dwell before retrieval).
struct StentRetrieverSpec {
  double diameter_mm = 0.0;                // 0: no stent
  double length_mm = 0.0;
  double embed_s = 180.0;
  [[nodiscard]] bool present() const { return diameter_mm > 0.0; }
  friend bool operator==(const StentRetrieverSpec&, const StentRetrieverSpec&) = default;
};

// How a catheter's tip follows the tools it carries (ToolSpec::steered_by_inner).
enum class InnerSteering : std::uint8_t {
  kNone,           // not steered (the coiling stack's microcatheter: docs/sim-tool/convergence.md)
  kAlways,         // a balloon catheter (the Simulator sets it): parked or advanced, its wire steers it
  kWhileAdvanced,  // an aspiration catheter (tool::steer_aspiration_catheters): while its hand advances it, or a wire or catheter leaving its tip is drawn back
};

struct ToolSpec {
  std::string name = "guidewire";
  ToolKind kind = ToolKind::kGuidewire;
  std::vector<ToolSection> sections;       // proximal first; the last one holds the tip
  double friction = 0.1;                   // Coulomb coefficient against the wall
  double inner_diameter_mm = 0.0;          // catheters: lumen diameter (0 for a guidewire)
  double lumen_friction = 0.05;            // catheters: Coulomb coefficient of the lumen liner
  // Catheters: whether the tools it carries steer its tip after them (their lean on the clamp at
  // its tip pushes it sideways; sim/tool README, "Coaxial tools"). Not recorded.
  InnerSteering steered_by_inner = InnerSteering::kNone;
  double axial_stiffness_N = 5000.0;       // EA; large, the tool is nearly inextensible
  // Viscous drag per mm of tool per mm/s. Default (none set): blood's, from its viscosity
  // (blood_drag_mN_s_per_mm2); a value here replaces it (e.g. a bench model in glycerol).
  std::optional<double> drag_mN_s_per_mm2;
  double blood_viscosity_mPa_s = 3.5;      // the case's blood (sim/flow's `viscosity`)
  // Coulomb friction of the haemostatic valve the tool slides through (the sheath's for a tool
  // in the vessel, the catheter hub's for a coaxial one), felt at the hand as a constant force
  // against the motion (stick, then slip). Default (none set): kDefaultValveFriction_mN.
  std::optional<double> valve_friction_mN;
  double max_spacing_mm = 2.0;             // node spacing along the shaft
  double tip_spacing_mm = 0.5;             // node spacing over the distal tip_zone_mm
  double tip_zone_mm = 10.0;
  std::string inside;                      // name of the catheter this one runs in, or ""
  double detach_mm = 0.0;                  // coils: length of the detachable coil at the tip
  // Coils: the coils loaded after the first, in order, each on a new pusher like the first
  // (the sections proximal of the first coil's detach_mm): one section each (length = the coil's
  // length, its primary wind and secondary shape). Simulator::load_next_coil takes the next.
  std::vector<ToolSection> next_coils;
  BalloonSpec balloon;                     // balloon catheters
  StentRetrieverSpec stent;                // a guidewire carrying a stent retriever (its push wire)

  // The drag coefficient (mN.s/mm2) at a station of this outer radius.
  [[nodiscard]] double drag_at(double radius_mm) const;
  [[nodiscard]] double valve_friction() const;

  [[nodiscard]] double length_mm() const {
    double total = 0.0;
    for (const ToolSection& s : sections) total += s.length_mm;
    return total;
  }
  // The widest section, next coils included (what must fit the catheter around the tool).
  [[nodiscard]] double max_outer_diameter_mm() const {
    double od = 0.0;
    for (const ToolSection& s : sections) od = od > s.outer_diameter_mm ? od : s.outer_diameter_mm;
    for (const ToolSection& s : next_coils) od = od > s.outer_diameter_mm ? od : s.outer_diameter_mm;
    return od;
  }
};

// A haemostatic valve's friction on a tool, when the case does not say (an estimate: a slit
// or Tuohy-Borst valve opened for the wire holds it with some tens of mN; calibrate per rig).
inline constexpr double kDefaultValveFriction_mN = 20.0;
// The lumen around a tool in the vessel for its drag (carotid and cerebral arteries: 1-3 mm).
inline constexpr double kNominalLumenRadius_mm = 2.0;

// Viscous drag of blood on a cylinder of radius a sliding axially at the centre of a tube of
// radius R (steady annular Couette flow): F / (L v) = 2 pi mu / ln(R / a). For a 0.36 mm wire
// in blood (3.5 mPa.s) in a 2 mm lumen: 9.1e-6 mN.s/mm2, i.e. 0.03 mN for 180 mm at 20 mm/s.
[[nodiscard]] double blood_drag_mN_s_per_mm2(double radius_mm, double viscosity_mPa_s,
                                             double lumen_radius_mm = kNominalLumenRadius_mm);

// The limits a tool must keep (the case file checks them statement by statement).
struct ToolLimits {
  static constexpr std::size_t kMaxTools = 6;  // balloon-assisted coiling: guide, balloon catheter and its wire, microcatheter, microwire, coil
  static constexpr std::size_t kMaxSections = 64;
  static constexpr double kMaxLength_mm = 4000.0;
  static constexpr double kMaxNodes = 6000.0;
  static constexpr double kMaxDiameter_mm = 20.0;
  static constexpr double kMaxStiffness_Nmm2 = 1e6;
  static constexpr double kMaxCurve_deg = 360.0;
  static constexpr double kMaxFriction = 2.0;
  static constexpr double kMaxSpacing_mm = 2.0;
  static constexpr double kMinTipSpacing_mm = 0.1;
  static constexpr double kMaxTipZone_mm = 500.0;
  static constexpr double kMaxDrag = 10.0;
  static constexpr double kMaxValveFriction_mN = 2000.0;
  static constexpr double kMinViscosity_mPa_s = 0.5;
  static constexpr double kMaxViscosity_mPa_s = 20.0;
  static constexpr double kMinAxialStiffness_N = 10.0;
  static constexpr double kMaxAxialStiffness_N = 1e6;
};

// Coils a coil tool may carry: the first and at most 15 loaded after it (`next_coil`).
inline constexpr std::size_t kMaxNextCoils = 15;

// The coil tool `spec` with its next coil `next` (spec.next_coils[next]) at its tip: the
// pusher (the sections proximal of the first coil's detach_mm) carrying that coil, its
// detach_mm the coil's length, the tip zone grown or shrunk with it; no further next coils.
[[nodiscard]] ToolSpec with_next_coil(const ToolSpec& spec, std::size_t next);

// True when following `inside` from tools[i] comes back to it (or never ends).
[[nodiscard]] bool nesting_cycle(std::span<const ToolSpec> tools, std::size_t i);

// Checks a set of tools as a simulator takes them (every value in range, names unique, coaxial
// tools inside a known catheter they fit in): "" when fine, else one line naming the tool and
// the value. For tools that did not come from a case file (a session record).
[[nodiscard]] std::string check_tools(std::span<const ToolSpec> tools);
// One tool's values (the first part of check_tools; a coil's next coils each as the tool it
// becomes once loaded).
[[nodiscard]] std::string check_tool(const ToolSpec& t);
// Why a balloon does not fit the limits (empty when it does): working length (0, 100] mm within
// the tool, distal end [0, 100] mm from the tip, nominal (0, 30] atm, rated burst in
// [nominal, 30] atm, a chart of 1..16 points with increasing pressures in (0, 30] atm and
// non-decreasing diameters in (0, 20] mm.
[[nodiscard]] std::string check_balloon(const BalloonSpec& b, double tool_length_mm);
// Why a stent retriever does not fit the limits (empty when it does): diameter [3, 6] mm,
// length [20, 40] mm and shorter than the tool, embedding time (0, 1800] s.
[[nodiscard]] std::string check_stent_retriever(const StentRetrieverSpec& s, double tool_length_mm);

}  // namespace cathbox::tool
