#include "ring_arcs.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace cathbox::vessel::detail {
namespace {

constexpr double kEndGapSpacing = 0.35;  // HCLM points closer to a trimmed end (in spacings) get no ring
constexpr double kRadiusStep = 0.1;      // largest radius change between adaptive rings, of the radius
constexpr int kMaxRingsPerSpan = 16;     // adaptive rings between two HCLM points, at most
constexpr double kSpacingGrowth = 2.0;   // next to added rings, a span at most this times its neighbour

}  // namespace

void adaptive_ring_arcs(const Polyline& pl, double a, double b, std::vector<double>& arcs) {
  // Every HCLM point strictly inside (a, b), except one closer to a trimmed end than a third of
  // its spacing to the next point (the end ring stands for it).
  std::vector<double> points{a};
  const std::size_t n = pl.arc.size();
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double t = pl.arc[i];
    if (t - a < kEndGapSpacing * (pl.arc[i + 1] - t) || b - t < kEndGapSpacing * (t - pl.arc[i - 1])) continue;
    points.push_back(t);
  }
  points.push_back(b);
  // Between two of them the radius is linear; where it changes by more than kRadiusStep of
  // itself, rings are added evenly so that every step is below that.
  arcs.assign(1, a);
  std::vector<char> added;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const double r0 = sample_radius(pl, points[i]);
    const double r1 = sample_radius(pl, points[i + 1]);
    const double steps = std::ceil(std::abs(r1 - r0) / (kRadiusStep * std::max(r0, r1)) - 1e-9);
    const int extra = static_cast<int>(std::min(steps, static_cast<double>(kMaxRingsPerSpan))) - 1;
    for (int k = 1; k <= extra; ++k) arcs.push_back(points[i] + (points[i + 1] - points[i]) * k / (extra + 1));
    arcs.push_back(points[i + 1]);
    added.resize(arcs.size() - 1, static_cast<char>(extra > 0));
  }
  grade_ring_spacing(arcs, added, kSpacingGrowth);
}

// Rings added where the radius changes fast are closer together than the rest. Along the segment
// the limit is the uniform cubic B-spline of the rings in ring index, not in arc, so the spline
// the shrink compensation solves for overshoots where the spacing jumps (a 0.55 mm artery
// widening to 1.95 mm within 1.8 mm, rings 0.19 mm apart after a 0.98 mm step: its tube bent
// ~0.05 mm off the axis, 5.3 % narrow at the ramp's foot). A span next to a span of added rings
// is split evenly if pieces of at most `growth` times that span take no more than two of them,
// else one such piece is cut off on that side, so the spacing grows geometrically away from the
// added rings. No piece is shorter than the finer neighbour (growth > 1), so this ends. Spans
// between HCLM points next to each other are left as they are (a centreline's own uneven steps:
// VMTK's 0.76 mm then 0.08 mm mesh within 0.5 % on a constant radius).
void grade_ring_spacing(std::vector<double>& arcs, std::vector<char>& added, double growth) {
  std::vector<double> cuts;
  std::size_t i = 0;
  while (i + 1 < arcs.size()) {
    const double len = arcs[i + 1] - arcs[i];
    const double left = i > 0 && added[i - 1] != 0 ? arcs[i] - arcs[i - 1] : len;
    const double right = i + 2 < arcs.size() && added[i + 1] != 0 ? arcs[i + 2] - arcs[i + 1] : len;
    const double fine = std::min(left, right);
    if (fine <= 0.0 || len <= growth * fine * (1.0 + 1e-9)) {
      ++i;
      continue;
    }
    cuts.clear();
    if (len <= 2.0 * growth * fine) {
      const int pieces = static_cast<int>(std::ceil(len / (growth * fine) - 1e-9));
      for (int k = 1; k < pieces; ++k) cuts.push_back(arcs[i] + len * k / pieces);
    } else {
      cuts.push_back(left <= right ? arcs[i] + growth * fine : arcs[i + 1] - growth * fine);
    }
    const auto at = static_cast<std::ptrdiff_t>(i);
    arcs.insert(arcs.begin() + at + 1, cuts.begin(), cuts.end());
    added[i] = 1;
    added.insert(added.begin() + at, cuts.size(), 1);
    i = i > 0 ? i - 1 : 0;
  }
}

}  // namespace cathbox::vessel::detail
