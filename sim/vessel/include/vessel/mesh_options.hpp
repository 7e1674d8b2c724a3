#pragma once
// Parameters of the HCLM -> surface pipeline.
namespace cathbox::vessel {

// How the centerline (positions and radii) is smoothed before the rings are placed.
//  kTaubin: Taubin's lambda|mu filter (lambda 0.5, mu -0.5263, pass band k_PB = 0.1): removes
//           point-to-point noise but does not shrink curves (a circle sampled every R/5 or closer
//           keeps its radius within 0.5 %) nor flatten radius changes spanning several points.
//  kMovingAverage: the thesis' (1,2,1) filter (3.2.3.2, eq. 2); shrinks curves and low-passes
//           the radius (three passes move a 13.5 mm arc sampled every mm inward by ~0.05 mm).
enum class SmoothingMethod { kTaubin, kMovingAverage };

// Where the rings of a segment go.
//  kAdaptive: a ring at every HCLM point inside the trimmed part of the segment, plus rings
//             between points wherever the radius changes by more than a tenth of itself from one
//             ring to the next (a stenosis or a bulge), so the surface follows the radius profile.
//  kPerPoint: exactly one ring per HCLM point, spread over the trimmed part at the points'
//             relative arc positions (the thesis' count: 4 sum k_i control points for M = 4).
enum class RingPlacement { kAdaptive, kPerPoint };

// How the refined vertices are moved to the limit surface:
//  kMasks: the Catmull-Clark limit position and tangent masks (Halstead et al. 1993) applied to
//          the last level. OpenSubdiv refines to level L-1; on a closed mesh without creases
//          the last step is done with PrimvarRefiner's own smooth weights in the same order
//          straight into the limit pass (so OpenSubdiv never builds level L), otherwise as
//          kMasksOnRefinedLevel. Cross-checked against the other two in the tests.
//  kMasksOnRefinedLevel: the same masks on level L as OpenSubdiv refines it (faces only) and
//          PrimvarRefiner interpolates it; kMasks must give exactly this mesh.
//  kOpenSubdiv: Far::PrimvarRefiner::Limit() with full topology in the last level.
enum class LimitMethod { kMasks, kMasksOnRefinedLevel, kOpenSubdiv };

struct MeshOptions {
  int smoothing_passes = 3;       // smoothing passes over centerline and radius (a Taubin pass is one lambda|mu pair)
  SmoothingMethod smoothing = SmoothingMethod::kTaubin;
  RingPlacement ring_placement = RingPlacement::kAdaptive;
  int ring_points = 8;            // M: points per cross-section ring (>= 3; 4 reproduces the thesis)
  int subdivision_level = 2;      // L: uniform Catmull-Clark level (0 = the control mesh itself)
  bool caps = true;               // close free ends with smooth caps (off: open tube ends)
  bool compensate_shrink = true;  // scale rings so the limit surface has the HCLM radius
  // Trim segments at junctions so branches have room (off: a ring at every HCLM point as the
  // thesis does, which reproduces its control-mesh counts but needs well separated branches).
  bool trim_at_junctions = true;
  // Move the limit surface of long junction patches (narrow branch angles) onto the branches'
  // tubes away from the crotch (see src/junction_fit.hpp).
  bool fit_junctions = true;
  // A junction whose rings' convex hull is no patch (branches overlap: too short or too close to
  // part, or folding back) takes its patch's connectivity from the hull of the branches'
  // directions on a sphere instead (src/junction_patch.hpp), so every valid model meshes closed;
  // ControlMesh::fallback_junctions names them. Off: such a junction is an error.
  bool junction_fallback = true;
  LimitMethod limit_method = LimitMethod::kMasks;  // the others are the peers the tests and benchmarks check against
};

}  // namespace cathbox::vessel
