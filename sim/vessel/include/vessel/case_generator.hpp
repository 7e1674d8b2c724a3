#pragma once
// Procedural vessel networks: the bundled neurovascular cases (aortic arch to the circle of
// Willis, with dimensions from the anatomical literature cited in src/neuro_case.cpp), their
// pathological variants (saccular aneurysm, stenosis), a simple Y bifurcation, and random trees
// and graphs for property tests and benchmarks. Every output is a valid VesselModel whose
// children start exactly at their parents' last points.
#include <cstdint>
#include <string>
#include <vector>

#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

struct RandomTreeOptions {
  int segments = 100;              // approximate number of segments (exact for trees: the
                                   // generator stops splitting once reached)
  double root_radius_mm = 3.0;
  double min_branch_angle_deg = 25.0;   // angle between a child and its parent's direction
  double max_branch_angle_deg = 60.0;
  double trifurcation_chance = 0.15;
  double spacing_radii = 1.2;      // centerline point spacing, in local radii
};

// Morphological variants of the neurovascular network (the case library, cases/library/;
// the published figures behind each are cited in src/neuro_case.cpp and sim/vessel/README.md).
enum class ArchType { kTypeI, kTypeII, kTypeIII, kBovine };
enum class IcaTortuosity { kStraight, kTortuous, kCoiled, kKinked };  // Weibel-Fields grades
enum class AneurysmSite { kNone, kAcom, kPcom, kBasilarTip, kMcaBifurcation };
// kElongated: from the parent's end, widening to the dome and 1.56 domes deep (the bundled 6.4 mm
// MCA sac); kRound: a sphere of the dome's diameter cut by the neck plane (the published small
// aneurysm's shape), that plane `neck_offset_mm` out along the sac's axis from the parent's end.
enum class SacShape { kElongated, kRound };

struct NeuroMorphology {
  ArchType arch = ArchType::kTypeI;
  IcaTortuosity left_ica = IcaTortuosity::kStraight;  // the cervical left ICA
  AneurysmSite aneurysm = AneurysmSite::kNone;
  double dome_mm = 6.4;  // saccular aneurysm: dome (sac) diameter
  double neck_mm = 2.4;  // and neck diameter
  SacShape sac_shape = SacShape::kElongated;
  double neck_offset_mm = 0.0;  // kRound: the neck plane's distance from the parent's end (the
                                // junction's patch, with the branch origins, lies behind it)
};

class CaseGenerator {
 public:
  // Names of the bundled cases: "neuro", "neuro_aneurysm", "neuro_small_aneurysm", "neuro_stenosis",
  // "y_bifurcation".
  [[nodiscard]] static std::vector<std::string> case_names();
  // The named case; an empty model for an unknown name.
  [[nodiscard]] static VesselModel make_case(const std::string& name);

  [[nodiscard]] static VesselModel neuro();            // healthy arch-to-Willis network
  [[nodiscard]] static VesselModel neuro_aneurysm();   // + saccular aneurysm at the right MCA bifurcation
  [[nodiscard]] static VesselModel neuro_small_aneurysm();  // the same site, a round 4.0 mm sac on a 1.8 mm neck
  [[nodiscard]] static VesselModel neuro_stenosis();   // + 70 % stenosis at the left ICA origin
  [[nodiscard]] static VesselModel y_bifurcation();    // one parent, two children (steering tests)
  // The arch-to-Willis network with the given morphology (neuro() is the default one).
  [[nodiscard]] static VesselModel neuro_variant(const NeuroMorphology& morphology);

  // Random binary/ternary tree (one root, branch angles in the given range).
  [[nodiscard]] static VesselModel random_tree(std::uint64_t seed, const RandomTreeOptions& options = {});
  // Random graph with `cycles` independent loops (a ring of segments with chords) plus
  // random side trees; bifurcations, trifurcations and confluences all occur.
  [[nodiscard]] static VesselModel random_graph(std::uint64_t seed, int cycles);
  // A single helical segment (for the twist property).
  [[nodiscard]] static VesselModel helix(double helix_radius_mm, double pitch_mm, double turns, double radius_mm,
                                         int points);
};

}  // namespace cathbox::vessel
