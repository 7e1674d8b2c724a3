#pragma once
// The aneurysm sac the coils fill: its neck (centre, radius and the plane that separates the
// sac from the parent artery), its dome (centre and radius) and its volume, the denominator of
// the packing density. Two sources:
//   - declared (case file `aneurysm`): a sphere of the dome's centre and radius cut by the neck
//     plane through the neck centre; the volume is the sphere cap beyond the plane,
//     pi h^2 (3R - h) / 3 with h = R + d (d: the centre's distance from the plane);
//   - found in the vessel: the segment named *aneurysm* (a blind sac, as sim/flow treats it).
//     The neck is its first centre-line point (the junction with the parent artery): centre,
//     radius, and the normal along the centre line. The vessel mesher gives the first
//     millimetres of the sac to the junction's surface patch; beyond them the sac's own
//     triangles and end cap, closed by a fan over their open ring, give the volume by the
//     divergence theorem, and the centre line's frusta add the part between neck and ring.
//     The dome centre is the surface part's centroid, its radius that of the sphere of the
//     sac's volume.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/surface_mesh.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::tool {

struct AneurysmSac {
  glm::dvec3 dome_centre_mm{0.0};
  double dome_radius_mm = 0.0;
  glm::dvec3 neck_centre_mm{0.0};
  double neck_radius_mm = 0.0;
  glm::dvec3 neck_normal{0.0, 0.0, 1.0};  // unit, from the parent artery into the sac
  double volume_mm3 = 0.0;
  std::int32_t segment = -1;              // the vessel segment of the sac; -1 when declared

  // Signed distance from the neck plane, positive on the sac's side.
  [[nodiscard]] double depth_mm(const glm::dvec3& p) const;
};

// Volume of the cap of a sphere of radius r with height h (0 <= h <= 2r).
[[nodiscard]] double sphere_cap_volume_mm3(double radius_mm, double height_mm);

// A declared sac: the dome sphere (centre, radius) cut by the plane through `neck_centre`
// normal to the line from the neck centre to the dome centre. The neck centre must lie inside
// the sphere, off its centre (else nullopt).
[[nodiscard]] std::optional<AneurysmSac> sphere_cap_sac(const glm::dvec3& dome_centre_mm, double dome_radius_mm,
                                                        const glm::dvec3& neck_centre_mm);

// Volume enclosed by triangles that form a closed surface once their open boundary (one ring)
// is closed by a fan to `apex` (any point of the ring's plane; outward-oriented triangles).
[[nodiscard]] double fan_closed_volume_mm3(std::span<const glm::vec3> positions, std::span<const std::uint32_t> triangles,
                                           const glm::dvec3& apex_mm);

// The sac of the first segment whose name contains "aneurysm", from the vessel surface built
// on `model`; nullopt when there is none (or its surface does not form one open ring).
[[nodiscard]] std::optional<AneurysmSac> find_sac(const vessel::VesselModel& model, const vessel::SurfaceMesh& mesh);

// Volume of the frusta (pi h (r1^2 + r1 r2 + r2^2) / 3) of a segment's centre line between two
// arc lengths from its start, and the arc length of the centre-line point closest to p.
[[nodiscard]] double frusta_volume_mm3(const vessel::Segment& sac, double from_mm, double to_mm);
[[nodiscard]] double arc_length_at(const vessel::Segment& sac, const glm::dvec3& p);

// The sac's volume from its centre line alone: its frusta from `from_mm` on and the half
// spheroid (r, r, r/2) the mesher closes its free end with; a cross-check of find_sac.
[[nodiscard]] double centreline_sac_volume_mm3(const vessel::Segment& sac, double from_mm = 0.0);

}  // namespace cathbox::tool
