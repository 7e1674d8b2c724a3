#pragma once
// Parameters of the HCLM -> surface pipeline.
namespace cathbox::vessel {

struct MeshOptions {
  int smoothing_passes = 3;       // (1,2,1) moving-average passes over centerline and radius
  int ring_points = 8;            // M: points per cross-section ring (>= 3; 4 reproduces the thesis)
  int subdivision_level = 2;      // L: uniform Catmull-Clark level (0 = the control mesh itself)
  bool caps = true;               // close free ends with smooth caps (off: open tube ends)
  bool compensate_shrink = true;  // scale rings so the limit surface has the HCLM radius
  // Trim segments at junctions so branches have room (off: a ring at every HCLM point as the
  // thesis does, which reproduces its control-mesh counts but needs well separated branches).
  bool trim_at_junctions = true;
};

}  // namespace cathbox::vessel
