#pragma once
// A vessel network drawn through knots, the generated cases' one drawing tool: each segment is a
// centripetal Catmull-Rom curve through its knots (position and radius), sampled about
// `spacing_radii` local radii apart (denser in bends); children start at their parents' end.
#include <cstdint>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/vessel_model.hpp"

namespace cathbox::vessel::detail {


struct Knot {
  glm::dvec3 pos_mm;
  double radius_mm;
};

// A segment's radius along it (arc and length in mm, the knots' interpolated radius in).
using RadiusProfile = std::function<double(double arc_mm, double length_mm, double radius_mm)>;

class Network {
 public:
  explicit Network(double spacing_radii = 0.9) : spacing_radii_(spacing_radii) {}

  // Adds a segment along a smooth curve through the knots (the first knot is where it starts;
  // for a child that is its parents' common end point). Returns the segment id.
  std::int32_t add(const std::string& name, const std::vector<Knot>& knots, std::vector<std::int32_t> parents,
                   double flow = 0.0, const RadiusProfile& profile = nullptr, double spacing_radii = 0.0);

  // Adds a segment joining two existing ends (a communicating artery closing a loop): it
  // starts where `from` ends and ends where every segment in `into` starts.
  std::int32_t add_link(const std::string& name, std::int32_t from, const std::vector<glm::dvec3>& inner,
                        const glm::dvec3& to, double radius_mm, const std::vector<std::int32_t>& into);

  [[nodiscard]] glm::dvec3 end(std::int32_t id) const {
    return model_.segments[static_cast<std::size_t>(*model_.index_of(id))].points.back().pos_mm;
  }
  [[nodiscard]] VesselModel take() { return std::move(model_); }

 private:
  [[nodiscard]] std::vector<CenterlinePoint> sample(const std::vector<Knot>& knots, const RadiusProfile& profile,
                                                    double spacing_radii) const;

  double spacing_radii_;
  std::int32_t next_id_ = 1;
  VesselModel model_;
};

}  // namespace cathbox::vessel::detail
