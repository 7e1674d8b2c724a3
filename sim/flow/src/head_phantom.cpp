#include "flow/head_phantom.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::flow {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Interval {
  double lo = kInf, hi = -kInf;
  [[nodiscard]] bool empty() const { return !(hi > lo); }
};

Interval intersect(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::min(a.hi, b.hi)}; }

// Ray parameters where o + t d lies within [lo, hi] along one axis.
Interval slab(double o, double d, double lo, double hi) {
  if (std::abs(d) < 1e-15) return (o >= lo && o <= hi) ? Interval{-kInf, kInf} : Interval{};
  const double t0 = (lo - o) / d, t1 = (hi - o) / d;
  return {std::min(t0, t1), std::max(t0, t1)};
}

// Roots of a t^2 + b t + c <= 0 (a > 0), as an interval.
Interval quadratic(double a, double b, double c) {
  if (a < 1e-15) return c <= 0.0 ? Interval{-kInf, kInf} : Interval{};
  const double disc = b * b - 4.0 * a * c;
  if (disc <= 0.0) return {};
  const double s = std::sqrt(disc);
  return {(-b - s) / (2.0 * a), (-b + s) / (2.0 * a)};
}

}  // namespace

double HeadPhantom::chord_mm(const PhantomShape& s, const glm::dvec3& o, const glm::dvec3& d) {
  Interval in{0.0, kInf};
  in = intersect(in, slab(o.z, d.z, s.z_min_mm, s.z_max_mm));
  in = intersect(in, slab(o.y, d.y, s.y_min_mm, 1e9));
  const glm::dvec3 p = o - s.center_mm;
  switch (s.kind) {
    case ShapeKind::kEllipsoid: {
      const glm::dvec3 q = p / s.half_mm, e = d / s.half_mm;
      in = intersect(in, quadratic(glm::dot(e, e), 2.0 * glm::dot(q, e), glm::dot(q, q) - 1.0));
      break;
    }
    case ShapeKind::kCylinderZ: {
      const double qx = p.x / s.half_mm.x, qy = p.y / s.half_mm.y, ex = d.x / s.half_mm.x, ey = d.y / s.half_mm.y;
      in = intersect(in, quadratic(ex * ex + ey * ey, 2.0 * (qx * ex + qy * ey), qx * qx + qy * qy - 1.0));
      in = intersect(in, slab(p.z, d.z, -s.half_mm.z, s.half_mm.z));
      break;
    }
    case ShapeKind::kBox:
      in = intersect(in, slab(p.x, d.x, -s.half_mm.x, s.half_mm.x));
      in = intersect(in, slab(p.y, d.y, -s.half_mm.y, s.half_mm.y));
      in = intersect(in, slab(p.z, d.z, -s.half_mm.z, s.half_mm.z));
      break;
  }
  return in.empty() ? 0.0 : in.hi - in.lo;
}

double HeadPhantom::path_mu(const glm::dvec3& origin, const glm::dvec3& direction) const {
  double sum = 0.0;
  for (const PhantomShape& s : shapes_) sum += s.delta_mu_per_mm * chord_mm(s, origin, direction);
  return sum;
}

std::vector<float> HeadPhantom::project(const CArm& carm, int width, int height) const {
  std::vector<double> acc(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0.0);
  const glm::dvec3 source = carm.source_mm();
  for (const PhantomShape& s : shapes_) {
    // Pixel bounds of the shape's box (clipped by its z planes); the whole image if any
    // corner is not in front of the source.
    glm::dvec3 lo = s.center_mm - s.half_mm, hi = s.center_mm + s.half_mm;
    lo.z = std::max(lo.z, s.z_min_mm);
    hi.z = std::min(hi.z, s.z_max_mm);
    lo.y = std::max(lo.y, s.y_min_mm);
    if (hi.z < lo.z) continue;
    int x0 = 0, y0 = 0, x1 = width - 1, y1 = height - 1;
    bool bounded = true;
    double px_lo = kInf, px_hi = -kInf, py_lo = kInf, py_hi = -kInf;
    for (int c = 0; c < 8 && bounded; ++c) {
      const glm::dvec3 corner{(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
      if (carm.depth_mm(corner) <= 1.0) {
        bounded = false;
        break;
      }
      const glm::dvec2 px = carm.project_px(corner, width, height);
      px_lo = std::min(px_lo, px.x);
      px_hi = std::max(px_hi, px.x);
      py_lo = std::min(py_lo, px.y);
      py_hi = std::max(py_hi, px.y);
    }
    if (bounded) {
      x0 = std::max(0, static_cast<int>(std::floor(px_lo)) - 1);
      x1 = std::min(width - 1, static_cast<int>(std::ceil(px_hi)) + 1);
      y0 = std::max(0, static_cast<int>(std::floor(py_lo)) - 1);
      y1 = std::min(height - 1, static_cast<int>(std::ceil(py_hi)) + 1);
    }
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const glm::dvec3 ray = carm.pixel_ray(x + 0.5, y + 0.5, width, height);
        acc[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] +=
            s.delta_mu_per_mm * chord_mm(s, source, ray);
      }
    }
  }
  return std::vector<float>(acc.begin(), acc.end());
}

double HeadPhantom::central_transmission(const CArm& carm) const {
  // The central quarter of the field: half its side, on a 15 x 15 grid.
  const int n = 15;
  const int size = 1000;
  const double half_px = 0.25 * size * carm.pose().collimation;
  double sum = 0.0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double px = 0.5 * size + half_px * (2.0 * (i + 0.5) / n - 1.0);
      const double py = 0.5 * size + half_px * (2.0 * (j + 0.5) / n - 1.0);
      sum += std::exp(-path_mu(carm.source_mm(), carm.pixel_ray(px, py, size, size)));
    }
  }
  return sum / (n * n);
}

HeadPhantom HeadPhantom::neuro(double keV) {
  const double tissue = linear_attenuation_per_mm(XrayMaterial::kSoftTissue, keV);
  const double bone = linear_attenuation_per_mm(XrayMaterial::kCorticalBone, keV) - tissue;  // bone in tissue
  const double brain = linear_attenuation_per_mm(XrayMaterial::kBrain, keV) - tissue;
  const double lung = linear_attenuation_per_mm(XrayMaterial::kLung, keV) - tissue;
  const double air = -tissue;
  std::vector<PhantomShape> s;
  const auto ellipsoid = [&](const char* name, glm::dvec3 c, glm::dvec3 h, double mu, double zmin = -1e9, double zmax = 1e9) {
    s.push_back({name, ShapeKind::kEllipsoid, c, h, zmin, zmax, mu});
  };
  const auto cylinder = [&](const char* name, glm::dvec3 c, glm::dvec3 h, double mu, double ymin = -1e9) {
    PhantomShape shape{name, ShapeKind::kCylinderZ, c, h, -1e9, 1e9, mu};
    shape.y_min_mm = ymin;
    s.push_back(shape);
  };
  // Soft tissue in pieces along z that do not overlap: head (down to the chin), neck, chest.
  ellipsoid("head", {0, 5, 225}, {78, 98, 110}, tissue, 140.0);
  cylinder("neck", {0, -5, 90}, {52, 55, 50}, tissue);
  cylinder("chest", {0, -5, -80}, {160, 110, 120}, tissue);
  // Skull vault: 6 mm tables, cut at the skull base; brain within.
  ellipsoid("skull outer table", {0, 5, 240}, {73, 93, 88}, bone, 190.0);
  ellipsoid("skull inner table", {0, 5, 240}, {67, 87, 82}, -bone, 190.0);
  ellipsoid("brain", {0, 5, 240}, {67, 87, 82}, brain, 190.0);
  // Skull base (half of it air cells and foramina) and the dense petrous pyramids.
  ellipsoid("skull base", {0, 5, 190}, {62, 75, 9}, 0.5 * bone);
  ellipsoid("right petrous pyramid", {-33, -12, 203}, {18, 11, 7}, bone);
  ellipsoid("left petrous pyramid", {33, -12, 203}, {18, 11, 7}, bone);
  // Face: maxilla (thin walls around the sinuses), mandible (a U open behind) and its rami.
  ellipsoid("maxilla", {0, 60, 178}, {34, 22, 18}, 0.35 * bone);
  cylinder("mandible", {0, 18, 150}, {48, 55, 8}, 0.8 * bone, 8.0);
  cylinder("mandible inner", {0, 18, 150}, {40, 47, 8}, -0.8 * bone, 8.0);
  ellipsoid("right ramus", {-46, 8, 172}, {5, 13, 20}, 0.8 * bone);
  ellipsoid("left ramus", {46, 8, 172}, {5, 13, 20}, 0.8 * bone);
  // Airway.
  cylinder("pharynx", {0, 15, 160}, {12, 8, 18}, air);
  cylinder("trachea", {0, 22, 85}, {9, 9, 45}, air);
  // Atlas ring, dens, cervical vertebrae C2-C7 (bodies ~15 mm high, 4-5 mm discs).
  cylinder("atlas ring", {0, -14, 183}, {40, 24, 5}, bone);
  cylinder("atlas foramen", {0, -14, 183}, {30, 16, 5}, -bone);
  cylinder("dens", {0, -2, 183.5}, {5, 5, 8.5}, bone);
  const double body_z[6] = {167.5, 148.0, 129.0, 110.0, 91.0, 72.0};  // C2 .. C7 centres
  for (int v = 0; v < 6; ++v) {
    const double z = body_z[v];
    cylinder("vertebral body", {0, -6, z}, {10, 8, v == 0 ? 7.5 : 7.0}, bone);
    ellipsoid("posterior arch", {0, -30, z}, {12, 12, 5}, 0.6 * bone);
    ellipsoid("right transverse process", {-21, -11, z}, {11, 5, 4}, 0.6 * bone);
    ellipsoid("left transverse process", {21, -11, z}, {11, 5, 4}, 0.6 * bone);
  }
  // Chest: lungs, sternum, clavicles, thoracic vertebrae.
  ellipsoid("right lung", {-70, -5, -70}, {60, 80, 110}, lung, -1e9, 35.0);
  ellipsoid("left lung", {70, -5, -70}, {60, 80, 110}, lung, -1e9, 35.0);
  ellipsoid("sternum", {0, 92, -60}, {15, 6, 85}, 0.5 * bone);
  ellipsoid("right clavicle", {-60, 40, 40}, {60, 8, 8}, bone);
  ellipsoid("left clavicle", {60, 40, 40}, {60, 8, 8}, bone);
  for (int v = 0; v < 8; ++v) cylinder("thoracic vertebra", {0, -15.0 - 6.0 * v, 45.0 - 25.0 * v}, {16, 14, 10}, bone);
  return HeadPhantom(std::move(s));
}

}  // namespace cathbox::flow
