#include "vessel/case_generator.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include <glm/geometric.hpp>

#include "vessel/rotation_minimizing_frame.hpp"

namespace cathbox::vessel {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Patient coordinates used by the bundled cases (millimetres): x towards the patient's left,
// y anterior, z superior; the top of the aortic arch is near the origin.
//
// Dimensions (diameters unless stated; radii in the code are half of them):
//  [1] Hager A, Kaemmerer H, et al. Diameters of the thoracic aorta throughout life as measured
//      with helical CT. J Thorac Cardiovasc Surg 2002;123:1060-6. Ascending aorta ~28-32 mm,
//      arch ~26 mm, descending aorta ~22-24 mm in adults.
//  [2] Standring S (ed). Gray's Anatomy, 41st ed. Elsevier 2016. Brachiocephalic trunk 4-5 cm
//      long, ~12 mm wide; subclavian artery ~8-10 mm; vertebral artery arises from the first part
//      of the subclavian and ascends through the transverse foramina of C6-C1 (V1-V3), then
//      enters the skull through the foramen magnum (V4) and joins its fellow at the lower border
//      of the pons to form the basilar artery.
//  [3] Krejza J, Arkuszewski M, Kasner SE, et al. Carotid artery diameter in men and women and
//      the relation to body and neck size. Stroke 2006;37:1103-5. Common carotid ~6.1-6.5 mm,
//      internal carotid ~4.3-4.7 mm (distal to the bulb).
//  [4] Bouthillier A, van Loveren HR, Keller JT. Segments of the internal carotid artery: a new
//      classification. Neurosurgery 1996;38:425-33. Cervical, petrous, lacerum, cavernous
//      (the siphon's S curve), clinoid, ophthalmic and communicating segments.
//  [5] Rhoton AL Jr. The supratentorial arteries. Neurosurgery 2002;51(4 Suppl):S53-120.
//      Middle cerebral M1 ~14-16 mm long, ~2.5-3 mm (angiographic) wide; bifurcates into
//      superior and inferior M2 trunks (~2 mm).
//  [6] Perlmutter D, Rhoton AL Jr. Microsurgical anatomy of the anterior cerebral-anterior
//      communicating-recurrent artery complex. J Neurosurg 1976;45:259-72. A1 ~12.7 mm long,
//      ~2.3-2.6 mm wide; anterior communicating artery ~1.5 mm wide, 0.3-7 mm long.
//  [7] Saeki N, Rhoton AL Jr. Microsurgical anatomy of the upper basilar artery and the
//      posterior circle of Willis. J Neurosurg 1977;46:563-78. P1 ~7 mm long, ~2.1 mm wide;
//      posterior communicating artery ~12 mm long, ~1.2-1.5 mm wide.
//  [8] Smoker WR, Price MJ, Keyes WD, et al. High-resolution computed tomography of the basilar
//      artery: 1. Normal size and position. AJNR 1986;7:55-60. Basilar artery ~3-4 mm wide,
//      ~30 mm long; vertebral arteries (V4) ~3-3.5 mm.
//  [9] Wiebers DO, et al. (ISUIA) Unruptured intracranial aneurysms: natural history.
//      Lancet 2003;362:103-10. Most saccular aneurysms are < 10 mm; the MCA bifurcation is one
//      of the commonest sites.
// [10] North American Symptomatic Carotid Endarterectomy Trial (NASCET) Collaborators. N Engl J
//      Med 1991;325:445-53. Stenosis graded by diameter reduction at the ICA origin; >= 70 %
//      is severe.
// [11] Madhwal S, Rajagopal V, Bhatt DL, et al. Predictors of difficult carotid stenting as
//      determined by aortic arch angiography. J Invasive Cardiol 2008;20:200-4. Arch type by the
//      vertical distance of the brachiocephalic origin below the top of the arch, in common
//      carotid diameters: type I < 1, type II 1-2, type III > 2.
// [12] Layton KF, Kallmes DF, Cloft HJ, et al. Bovine aortic arch variant in humans: clarification
//      of a common misnomer. AJNR 2006;27:1541-2. The commonest variant (~13 % of patients,
//      "bovine arch") is a common origin of the brachiocephalic and left common carotid arteries.
// [13] Weibel J, Fields WS. Tortuosity, coiling, and kinking of the internal carotid artery.
//      Neurology 1965;15:7-18 and 462-8. Tortuosity: S- or C-shaped elongation; coiling: an
//      exaggerated S curve or a circular loop; kinking: an acute angle between two segments.
// [14] UCAS Japan Investigators (Morita A, et al.). The natural course of unruptured cerebral
//      aneurysms in a Japanese cohort. N Engl J Med 2012;366:2474-82. Mean size 5.7 mm; 3-4 mm
//      in 42 %, 5-6 mm in 28 %, 7-9 mm in 18 %; sites MCA 36 %, ICA-PCom 17 %, ACom 16 %,
//      basilar tip 7 %. A neck >= 4 mm or dome/neck < 2 is called wide.
// Where the literature gives a range the case takes a typical value; two liberties are taken
// for a clean mesh and say so where they occur (arch branch spacing, AComm length).
// ---------------------------------------------------------------------------------------------

struct Knot {
  glm::dvec3 pos_mm;
  double radius_mm;
};

using RadiusProfile = std::function<double(double arc_mm, double length_mm, double radius_mm)>;

// Centripetal Catmull-Rom point between p1 and p2 (alpha = 0.5), t in [0, 1].
[[nodiscard]] glm::dvec3 catmull_rom(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                                     const glm::dvec3& p3, double t) {
  const auto knot = [](double ti, const glm::dvec3& a, const glm::dvec3& b) {
    return ti + std::sqrt(std::max(glm::length(b - a), 1e-9));
  };
  const double t0 = 0.0;
  const double t1 = knot(t0, p0, p1);
  const double t2 = knot(t1, p1, p2);
  const double t3 = knot(t2, p2, p3);
  const double u = t1 + t * (t2 - t1);
  const glm::dvec3 a1 = (t1 - u) / (t1 - t0) * p0 + (u - t0) / (t1 - t0) * p1;
  const glm::dvec3 a2 = (t2 - u) / (t2 - t1) * p1 + (u - t1) / (t2 - t1) * p2;
  const glm::dvec3 a3 = (t3 - u) / (t3 - t2) * p2 + (u - t2) / (t3 - t2) * p3;
  const glm::dvec3 b1 = (t2 - u) / (t2 - t0) * a1 + (u - t0) / (t2 - t0) * a2;
  const glm::dvec3 b2 = (t3 - u) / (t3 - t1) * a2 + (u - t1) / (t3 - t1) * a3;
  return (t2 - u) / (t2 - t1) * b1 + (u - t1) / (t2 - t1) * b2;
}

class Network {
 public:
  explicit Network(double spacing_radii = 0.9) : spacing_radii_(spacing_radii) {}

  // Adds a segment along a smooth curve through the knots (the first knot is where it starts;
  // for a child that is its parents' common end point). Returns the segment id.
  std::int32_t add(const std::string& name, const std::vector<Knot>& knots, std::vector<std::int32_t> parents,
                   double flow = 0.0, const RadiusProfile& profile = nullptr, double spacing_radii = 0.0) {
    Segment s;
    s.id = next_id_++;
    s.name = name;
    s.flow = flow;
    s.parents = parents;
    s.points = sample(knots, profile, spacing_radii > 0.0 ? spacing_radii : spacing_radii_);
    for (std::int32_t p : parents) {
      model_.segments[static_cast<std::size_t>(*model_.index_of(p))].children.push_back(s.id);
    }
    model_.segments.push_back(std::move(s));
    return model_.segments.back().id;
  }

  // Adds a segment joining two existing ends (a communicating artery closing a loop): it
  // starts where `from` ends and ends where every segment in `into` starts.
  std::int32_t add_link(const std::string& name, std::int32_t from, const std::vector<glm::dvec3>& inner,
                        const glm::dvec3& to, double radius_mm, const std::vector<std::int32_t>& into) {
    std::vector<Knot> knots{{end(from), radius_mm}};
    for (const glm::dvec3& p : inner) knots.push_back({p, radius_mm});
    knots.push_back({to, radius_mm});
    const std::int32_t id = add(name, knots, {from});
    for (std::int32_t child : into) {
      model_.segments.back().children.push_back(child);
      model_.segments[static_cast<std::size_t>(*model_.index_of(child))].parents.push_back(id);
    }
    return id;
  }

  [[nodiscard]] glm::dvec3 end(std::int32_t id) const {
    return model_.segments[static_cast<std::size_t>(*model_.index_of(id))].points.back().pos_mm;
  }
  [[nodiscard]] VesselModel take() { return std::move(model_); }

 private:
  [[nodiscard]] std::vector<CenterlinePoint> sample(const std::vector<Knot>& knots, const RadiusProfile& profile,
                                                    double spacing_radii) const {
    // Dense polyline through the knots (end knots duplicated for the spline's end tangents).
    std::vector<glm::dvec3> dense;
    std::vector<double> dense_radius;
    const std::size_t n = knots.size();
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const glm::dvec3 p0 = i == 0 ? 2.0 * knots[0].pos_mm - knots[1].pos_mm : knots[i - 1].pos_mm;
      const glm::dvec3 p3 = i + 2 < n ? knots[i + 2].pos_mm : 2.0 * knots[n - 1].pos_mm - knots[n - 2].pos_mm;
      constexpr int kSteps = 48;
      for (int k = 0; k < kSteps; ++k) {
        const double t = static_cast<double>(k) / kSteps;
        dense.push_back(catmull_rom(p0, knots[i].pos_mm, knots[i + 1].pos_mm, p3, t));
        dense_radius.push_back(knots[i].radius_mm + t * (knots[i + 1].radius_mm - knots[i].radius_mm));
      }
    }
    dense.push_back(knots.back().pos_mm);
    dense_radius.push_back(knots.back().radius_mm);
    std::vector<double> arc(dense.size(), 0.0);
    for (std::size_t i = 1; i < dense.size(); ++i) arc[i] = arc[i - 1] + glm::length(dense[i] - dense[i - 1]);
    const double length = arc.back();
    const auto at = [&](double s) {
      const auto it = std::upper_bound(arc.begin(), arc.end(), s);
      std::size_t j = it == arc.begin() ? 0 : static_cast<std::size_t>(it - arc.begin()) - 1;
      j = std::min(j, arc.size() - 2);
      const double span = arc[j + 1] - arc[j];
      const double a = span > 0.0 ? std::clamp((s - arc[j]) / span, 0.0, 1.0) : 0.0;
      CenterlinePoint p;
      p.pos_mm = dense[j] + a * (dense[j + 1] - dense[j]);
      p.radius_mm = dense_radius[j] + a * (dense_radius[j + 1] - dense_radius[j]);
      if (profile) p.radius_mm = profile(s, length, p.radius_mm);
      return p;
    };
    // Curvature of the dense polyline (turning angle per length), to sample bends densely.
    std::vector<double> curvature(dense.size(), 0.0);
    for (std::size_t i = 1; i + 1 < dense.size(); ++i) {
      const glm::dvec3 a = dense[i] - dense[i - 1];
      const glm::dvec3 b = dense[i + 1] - dense[i];
      const double la = glm::length(a);
      const double lb = glm::length(b);
      if (la > 0.0 && lb > 0.0) {
        const double c = std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0);
        curvature[i] = std::acos(c) / (0.5 * (la + lb));
      }
    }
    const auto curvature_at = [&](double s) {
      const auto it = std::upper_bound(arc.begin(), arc.end(), s);
      return curvature[std::min(static_cast<std::size_t>(it - arc.begin()), curvature.size() - 1)];
    };
    // Points about spacing_radii local radii apart (at most 0.3 bend radii in bends), placed at
    // the same relative positions along the curve, at least 3.
    std::vector<double> stations{0.0};
    for (double s = 0.0; s < length;) {
      double h = std::max(0.3, spacing_radii * at(s).radius_mm);
      const double kappa = curvature_at(s);
      if (kappa > 0.0) h = std::max(0.3, std::min(h, 0.3 / kappa));
      s += h;
      stations.push_back(std::min(s, length));
    }
    const double overshoot = stations.back() - stations[stations.size() - 2];
    if (stations.size() > 2 && overshoot < 0.5 * (stations[stations.size() - 2] - stations[stations.size() - 3])) {
      stations.erase(stations.end() - 2);  // merge a sliver at the end
    }
    while (stations.size() < 3) stations.insert(stations.end() - 1, 0.5 * (stations[stations.size() - 2] + stations.back()));
    const double scale = length / stations.back();
    std::vector<CenterlinePoint> points;
    for (double station : stations) points.push_back(at(station * scale));
    points.front().pos_mm = knots.front().pos_mm;
    points.back().pos_mm = knots.back().pos_mm;
    return points;
  }

  double spacing_radii_;
  std::int32_t next_id_ = 1;
  VesselModel model_;
};

// Gaussian narrowing: `reduction` of the diameter at arc `center_mm`, half-width `width_mm`.
[[nodiscard]] RadiusProfile stenosis(double center_mm, double width_mm, double reduction) {
  return [=](double s, double, double r) {
    const double x = (s - center_mm) / width_mm;
    return r * (1.0 - reduction * std::exp(-x * x));
  };
}

// A saccular aneurysm as a blind segment (free end, capped) from `base` along `axis`: the neck
// diameter at the base, widening to the dome diameter, 1.56 domes deep (the bundled MCA sac: 2.4 mm
// neck, 6.4 mm dome, 10 mm deep).
[[nodiscard]] std::vector<Knot> sac_knots(const glm::dvec3& base, const glm::dvec3& axis, double neck_mm, double dome_mm) {
  const double s = dome_mm / 6.4;
  return {{base, 0.5 * neck_mm},           {base + 2.0 * s * axis, 2.0 * s}, {base + 4.5 * s * axis, 3.0 * s},
          {base + 6.5 * s * axis, 3.2 * s}, {base + 8.5 * s * axis, 2.6 * s}, {base + 10.0 * s * axis, 1.4 * s}};
}

// The aortic arch's shape for each arch type [11][12]: the arch is a half ellipse whose top stays
// put; `height_mm` is its vertical semi-axis and the branch origins (degrees along it, 90 = top)
// move down the ascending limb as the type rises. Vertical drop of the brachiocephalic origin
// below the arch top = height * (1 - sin(bct)): type I 5.4 mm (0.8 CCA diameters of 6.4 mm),
// type II 10.5 mm (1.6), type III 13.5 mm (2.1).
struct ArchShape {
  double height_mm, bct_deg, lcca_deg, lsa_deg;
};
[[nodiscard]] ArchShape arch_shape(ArchType type) {
  switch (type) {
    case ArchType::kTypeII: return {36.0, 45.0, 85.0, 130.0};
    case ArchType::kTypeIII: return {46.0, 45.0, 85.0, 130.0};
    default: return {30.0, 55.0, 95.0, 135.0};
  }
}

// Cervical left ICA knots between the bulb and the skull base (Weibel-Fields grades [13]):
// tortuous = S-shaped elongation, coiled = a full loop, kinked = an acute (< 90 degree) angle.
[[nodiscard]] std::vector<Knot> cervical_ica(IcaTortuosity t) {
  switch (t) {
    case IcaTortuosity::kTortuous:
      return {{{28, 14, 138}, 2.8}, {{34, 11, 150}, 2.6}, {{25, 12, 163}, 2.5}, {{30, 10, 175}, 2.4}};
    case IcaTortuosity::kCoiled:
      return {{{28, 14, 138}, 2.8}, {{28, 15, 148}, 2.7}, {{30, 15, 158}, 2.6}, {{37, 13, 165}, 2.6},
              {{44, 10, 158}, 2.5}, {{39, 6, 148}, 2.5}, {{31, 5, 152}, 2.45}, {{27, 7, 165}, 2.4},
              {{26, 9, 177}, 2.4}};
    case IcaTortuosity::kKinked:
      return {{{28, 14, 140}, 2.8}, {{33, 14, 151}, 2.6}, {{40, 14, 160}, 2.5}, {{35, 12, 165}, 2.45},
              {{29, 10, 172}, 2.4}};
    default: return {{{28, 14, 140}, 2.8}, {{27, 12, 160}, 2.4}};
  }
}

[[nodiscard]] glm::dvec3 mirror(const glm::dvec3& p) { return {-p.x, p.y, p.z}; }

VesselModel build_neuro(const NeuroMorphology& m, bool stenosed) {
  Network net;
  const ArchShape shape = arch_shape(m.arch);
  const bool bovine = m.arch == ArchType::kBovine;
  // Aortic arch [1]: the ascending aorta rises on the right and in front, the arch (a half
  // circle of ~30 mm centreline radius in an oblique plane) passes over to the left and back, and
  // the descending aorta goes down. Liberty: the three branch origins are 40 degrees (~21 mm)
  // apart along the arch (often closer in vivo) so each junction has room for its rings.
  const glm::dvec3 arch_center{0, 0, 18.0 - shape.height_mm};
  const glm::dvec3 anterior = glm::normalize(glm::dvec3(-0.35, 1.0, 0.0));
  const glm::dvec3 up{0, 0, 1};
  constexpr double kArchRadius = 30.0;
  const auto arch = [&](double deg) {
    const double a = deg * kPi / 180.0;
    return arch_center + kArchRadius * (std::cos(a) * anterior + (shape.height_mm / kArchRadius) * std::sin(a) * up);
  };
  const auto arch_normal = [&](double deg) {
    const double a = deg * kPi / 180.0;
    const glm::dvec3 n = std::cos(a) * (shape.height_mm / kArchRadius) * anterior + std::sin(a) * up;
    return shape.height_mm == kArchRadius ? n : glm::normalize(n);
  };
  const double bct_deg = shape.bct_deg;
  const double lcca_deg = shape.lcca_deg;
  const double lsa_deg = shape.lsa_deg;
  const auto mid = [](double a, double b) { return std::round(0.5 * (a + b)); };
  const std::int32_t arch1 = net.add("ascending_aorta",
                                     {{arch(0) - 60.0 * up, 15.0}, {arch(0) - 30.0 * up, 14.5}, {arch(0), 14.0},
                                      {arch(mid(0, bct_deg)), 13.7}, {arch(bct_deg), 13.5}},
                                     {}, 5000.0);
  // A bovine arch has no separate left carotid origin: one arch segment runs from the
  // brachiocephalic to the left subclavian origin.
  const std::int32_t arch2 =
      bovine ? net.add("aortic_arch_1",
                       {{arch(bct_deg), 13.5}, {arch(75), 13.2}, {arch(95), 13.0}, {arch(115), 12.7}, {arch(lsa_deg), 12.5}},
                       {arch1}, 4200.0)
             : net.add("aortic_arch_1", {{arch(bct_deg), 13.5}, {arch(mid(bct_deg, lcca_deg)), 13.2}, {arch(lcca_deg), 13.0}},
                       {arch1}, 4200.0);
  const std::int32_t arch3 =
      bovine ? arch2
             : net.add("aortic_arch_2", {{arch(lcca_deg), 13.0}, {arch(mid(lcca_deg, lsa_deg)), 12.7}, {arch(lsa_deg), 12.5}},
                       {arch2}, 3800.0);
  net.add("descending_aorta",
          {{arch(lsa_deg), 12.5}, {arch(mid(lsa_deg, 180.0)), 12.2}, {arch(180), 12.0}, {arch(180) - 30.0 * up, 11.8},
           {arch(180) - 70.0 * up, 11.5}},
          {arch3}, 3400.0);

  // Brachiocephalic trunk [2]: ~45 mm up and to the right, 12 mm wide.
  // On a high arch (types II, III) the trunk leaves the ascending limb tilted upwards.
  const glm::dvec3 bct_direction =
      shape.height_mm == kArchRadius ? arch_normal(bct_deg) : glm::normalize(arch_normal(bct_deg) + 0.8 * up);
  // Bovine arch [12]: the left common carotid shares the brachiocephalic origin (the common
  // trunk splits 16 mm above the arch).
  const std::int32_t bct_stem =
      bovine ? net.add("brachiocephalic_trunk",
                       {{arch(bct_deg), 6.2}, {arch(bct_deg) + 8.0 * arch_normal(bct_deg), 6.1},
                        {arch(bct_deg) + 16.0 * arch_normal(bct_deg), 6.0}},
                       {arch1}, 1220.0)
             : 0;
  const std::int32_t bct =
      bovine ? net.add("brachiocephalic_trunk_2", {{net.end(bct_stem), 5.9}, {{-13, 24, 38}, 5.9}, {{-17, 22, 50}, 5.8}},
                       {bct_stem}, 800.0)
             : net.add("brachiocephalic_trunk",
                       {{arch(bct_deg), 6.2}, {arch(bct_deg) + 16.0 * bct_direction, 6.0}, {{-13, 24, 38}, 5.9},
                        {{-17, 22, 50}, 5.8}},
                       {arch1}, 800.0);
  // Subclavian arteries [2] (~9 mm) with the vertebral arteries arising from their first part.
  const std::int32_t rsub1 = net.add("right_subclavian_1",
                                     {{net.end(bct), 4.6}, {{-28, 16, 56}, 4.5}, {{-40, 10, 58}, 4.4}}, {bct}, 350.0);
  net.add("right_subclavian_2", {{net.end(rsub1), 4.4}, {{-55, 6, 56}, 4.2}, {{-75, 4, 48}, 4.0}}, {rsub1}, 250.0);
  const std::int32_t lsub1 = net.add("left_subclavian_1",
                                     {{arch(lsa_deg), 5.0}, {arch(lsa_deg) + 16.0 * arch_normal(lsa_deg), 4.8},
                                      {{22, -30, 40}, 4.6},
                                      {{40, -20, 56}, 4.4}},
                                     {arch3}, 350.0);
  net.add("left_subclavian_2", {{net.end(lsub1), 4.4}, {{55, -16, 55}, 4.2}, {{75, -12, 46}, 4.0}}, {lsub1}, 250.0);

  // Common carotid arteries [3] (6.4 mm) up to the bifurcation at about C4.
  const std::int32_t rcca = net.add("right_common_carotid",
                                    {{net.end(bct), 3.3}, {{-20, 18, 75}, 3.25}, {{-24, 17, 100}, 3.2}, {{-26, 16, 125}, 3.2}},
                                    {bct}, 420.0);
  const std::int32_t lcca =
      bovine ? net.add("left_common_carotid",
                       {{net.end(bct_stem), 3.4}, {{0, 18, 42}, 3.35}, {{12, 10, 62}, 3.3}, {{18, 9, 80}, 3.25},
                        {{22, 12, 100}, 3.2}, {{26, 16, 125}, 3.2}},
                       {bct_stem}, 420.0)
             : net.add("left_common_carotid",
                       {{net.end(arch2), 3.4}, {net.end(arch2) + 14.0 * arch_normal(lcca_deg), 3.35},
                        {{8, -2, 50}, 3.3}, {{16, 6, 75}, 3.25}, {{22, 12, 100}, 3.2}, {{26, 16, 125}, 3.2}},
                       {arch2}, 420.0);

  struct Side {
    std::int32_t ica_top = 0;   // supraclinoid ICA ending at the PComm origin
    std::int32_t ica_term = 0;  // ICA terminal segment
    std::int32_t m1 = 0;
    std::int32_t a1 = 0;
  };
  const auto carotid_side = [&](bool left, std::int32_t cca) {
    const auto P = [left](double x, double y, double z) { return left ? glm::dvec3(x, y, z) : mirror({x, y, z}); };
    const std::string side = left ? "left_" : "right_";
    // External carotid (~4 mm), anteromedial, ending in the face.
    net.add(side + "external_carotid", {{net.end(cca), 2.1}, {P(24, 22, 140), 2.0}, {P(28, 30, 160), 1.8}}, {cca}, 150.0);
    // Internal carotid [3][4]: carotid bulb (dilated origin), cervical ascent to the skull base,
    // petrous segment turning anteromedially, cavernous siphon (S curve: posterior bend, anterior
    // genu), clinoid/ophthalmic segment turning back up to the PComm origin.
    RadiusProfile profile = nullptr;
    if (left && stenosed) profile = stenosis(12.0, 4.0, 0.7);  // [10] 70 % at the bulb
    std::vector<Knot> ica_knots{{net.end(cca), 3.0}};
    for (const Knot& k : cervical_ica(left ? m.left_ica : IcaTortuosity::kStraight)) ica_knots.push_back({P(k.pos_mm.x, k.pos_mm.y, k.pos_mm.z), k.radius_mm});
    for (const Knot& k : std::vector<Knot>{{P(26, 10, 185), 2.35}, {P(22, 16, 196), 2.3}, {P(18, 24, 200), 2.25},
                                      {P(17, 30, 206), 2.2}, {P(16, 33, 214), 2.1}, {P(15, 28, 222), 2.0},
                                      {P(14, 14, 226), 1.95}}) {
      ica_knots.push_back(k);
    }
    const std::int32_t ica = net.add(side + "internal_carotid", ica_knots, {cca}, 250.0, profile);
    Side s;
    s.ica_top = ica;
    s.ica_term = net.add(side + "internal_carotid_terminal", {{net.end(ica), 1.9}, {P(14, 14, 231), 1.85}, {P(14, 15, 236), 1.8}},
                         {ica}, 220.0);
    // M1 [5]: ~16 mm laterally, 2.8 mm.
    s.m1 = net.add(side + "middle_cerebral_m1", {{net.end(s.ica_term), 1.45}, {P(22, 16, 237), 1.4}, {P(31, 16, 239), 1.35}},
                   {s.ica_term}, 130.0);
    const std::int32_t m1 = s.m1;
    net.add(side + "middle_cerebral_m2_superior", {{net.end(m1), 1.05}, {P(34, 18, 249), 1.0}, {P(40, 21, 262), 0.95}},
            {m1}, 65.0);
    net.add(side + "middle_cerebral_m2_inferior", {{net.end(m1), 1.05}, {P(35, 13, 230), 1.0}, {P(44, 9, 222), 0.95}},
            {m1}, 65.0);
    if (!left && m.aneurysm == AneurysmSite::kMcaBifurcation) {
      // [9] Saccular aneurysm at the (right) MCA bifurcation, pointing along the M1 axis.
      const glm::dvec3 base = net.end(m1);
      net.add(side + "mca_aneurysm", sac_knots(base, glm::normalize(base - P(22, 16, 237)), m.neck_mm, m.dome_mm), {m1}, 0.0,
              nullptr, 0.35);
    }
    if (left && m.aneurysm == AneurysmSite::kPcom) {
      // [9][14] Left posterior communicating aneurysm: from the ICA wall at the PComm origin,
      // pointing posterolaterally and down (the usual projection).
      net.add(side + "pcom_aneurysm", sac_knots(net.end(ica), glm::normalize(glm::dvec3(1.0, -0.5, -0.35)), m.neck_mm, m.dome_mm),
              {ica}, 0.0, nullptr, 0.35);
    }
    // A1 [6]: ~13 mm medially and anteriorly, 2.3 mm; ends at the AComm.
    s.a1 = net.add(side + "anterior_cerebral_a1", {{net.end(s.ica_term), 1.2}, {P(9, 20, 238), 1.15}, {P(3, 27, 240), 1.1}},
                   {s.ica_term}, 70.0);
    return s;
  };
  const Side right = carotid_side(false, rcca);
  const Side left = carotid_side(true, lcca);

  // Vertebral arteries [2][8] (~3.6 mm): V1 up to C6, V2 through the transverse foramina, V3
  // loop behind the atlas, V4 through the foramen magnum to the vertebrobasilar junction.
  const glm::dvec3 vb_junction{0, -6, 200};
  const auto vertebral = [&](bool left_side, std::int32_t subclavian) {
    const auto P = [left_side](double x, double y, double z) {
      return left_side ? glm::dvec3(x, y, z) : mirror({x, y, z});
    };
    return net.add(std::string(left_side ? "left_" : "right_") + "vertebral",
                   {{net.end(subclavian), 1.9}, {P(38, -8, 80), 1.85}, {P(30, -12, 110), 1.8}, {P(28, -14, 150), 1.8},
                    {P(30, -18, 168), 1.75}, {P(26, -26, 178), 1.7}, {P(14, -20, 186), 1.65}, {P(6, -11, 194), 1.6},
                    {vb_junction, 1.6}},
                   {subclavian}, 100.0);
  };
  const std::int32_t rva = vertebral(false, rsub1);
  const std::int32_t lva = vertebral(true, lsub1);
  // Basilar artery [8]: ~32 mm along the clivus, 3.2 mm; a confluence of the two vertebrals.
  const std::int32_t basilar =
      net.add("basilar", {{vb_junction, 1.65}, {{0, -3, 215}, 1.6}, {{0, -1, 232}, 1.55}}, {lva, rva}, 190.0);
  if (m.aneurysm == AneurysmSite::kBasilarTip) {
    // [9][14] Basilar tip aneurysm: along the basilar axis, between the two P1 origins.
    net.add("basilar_tip_aneurysm", sac_knots(net.end(basilar), glm::normalize(glm::dvec3(0, 0.12, 1)), m.neck_mm, m.dome_mm),
            {basilar}, 0.0, nullptr, 0.35);
  }
  // P1 [7]: ~7 mm, 2.1 mm; PComm [7] joins at the P1/P2 junction; P2 runs around the midbrain.
  const auto posterior = [&](bool left_side, const Side& s) {
    const auto P = [left_side](double x, double y, double z) {
      return left_side ? glm::dvec3(x, y, z) : mirror({x, y, z});
    };
    const std::string side = left_side ? "left_" : "right_";
    const std::int32_t p1 = net.add(side + "posterior_cerebral_p1", {{net.end(basilar), 1.05}, {P(4, -1, 233), 1.05},
                                                                      {P(9, 0, 235), 1.0}},
                                    {basilar}, 45.0);
    const std::int32_t p2 = net.add(side + "posterior_cerebral_p2",
                                    {{net.end(p1), 1.0}, {P(17, -8, 238), 0.95}, {P(24, -22, 242), 0.95}, {P(28, -40, 246), 0.9}},
                                    {p1}, 50.0);
    // PComm [7]: from the ICA (at the end of the supraclinoid segment) back to the P1/P2 junction.
    net.add_link(side + "posterior_communicating", s.ica_top, {P(12, 7, 230)}, net.end(p1), 0.7, {p2});
  };
  posterior(false, right);
  posterior(true, left);

  // A2 and the anterior communicating artery [6]. Liberty: the AComm is 6 mm (range 0.3-7 mm)
  // so both A1/A2 junctions have room.
  const std::int32_t a2_right = net.add("right_anterior_cerebral_a2",
                                        {{net.end(right.a1), 1.1}, {{-3.5, 33, 252}, 1.05}, {{-3.5, 40, 270}, 1.0}},
                                        {right.a1}, 60.0);
  net.add("left_anterior_cerebral_a2", {{net.end(left.a1), 1.1}, {{3.5, 33, 252}, 1.05}, {{3.5, 40, 270}, 1.0}},
          {left.a1}, 60.0);
  if (m.aneurysm == AneurysmSite::kAcom) {
    // [9][14] Anterior communicating aneurysm: from the middle of the AComm, pointing
    // anteriorly and up; the AComm is split there.
    const std::int32_t acomm =
        net.add("anterior_communicating", {{net.end(left.a1), 0.75}, {{0, 28.5, 241}, 0.75}}, {left.a1});
    net.add("acom_aneurysm", sac_knots(net.end(acomm), glm::normalize(glm::dvec3(0, 0.7, 0.7)), m.neck_mm, m.dome_mm),
            {acomm}, 0.0, nullptr, 0.35);
    net.add_link("anterior_communicating_2", acomm, {}, net.end(right.a1), 0.75, {a2_right});
  } else {
    net.add_link("anterior_communicating", left.a1, {{0, 28.5, 241}}, net.end(right.a1), 0.75, {a2_right});
  }
  return net.take();
}

// Deterministic uniform numbers (independent of the standard library's distributions).
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0);
  }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }

 private:
  std::mt19937_64 engine_;
};

[[nodiscard]] glm::dvec3 rotate(const glm::dvec3& v, const glm::dvec3& axis, double angle_rad) {
  const glm::dvec3 k = glm::normalize(axis);
  return v * std::cos(angle_rad) + glm::cross(k, v) * std::sin(angle_rad) +
         k * glm::dot(k, v) * (1.0 - std::cos(angle_rad));
}

// A gently curved path of length `length` starting at `start` in direction `dir`.
[[nodiscard]] std::vector<Knot> curved_path(Random& rng, const glm::dvec3& start, const glm::dvec3& dir, double length,
                                            double r0, double r1) {
  const glm::dvec3 side = any_perpendicular(dir);
  const glm::dvec3 bend_axis = rotate(side, dir, rng.uniform(0.0, 2.0 * kPi));
  const double bend = rng.uniform(-0.25, 0.25);
  const glm::dvec3 mid_dir = rotate(dir, bend_axis, 0.5 * bend);
  const glm::dvec3 end_dir = rotate(dir, bend_axis, bend);
  const glm::dvec3 mid = start + 0.5 * length * mid_dir;
  return {{start, r0}, {mid, 0.5 * (r0 + r1)}, {mid + 0.5 * length * end_dir, r1}};
}

// random_graph's steps: a ring of junctions joined by ring segments, chords across the ring and
// a side branch per junction; the parent / child relations written once every segment is known.
class RandomGraphBuilder {
 public:
  RandomGraphBuilder(std::uint64_t seed, int cycles) : rng_(seed), cycles_(std::max(cycles, 1)), n_(cycles_ + 2) {
    place_junctions();
  }

  VesselModel build() {
    add_ring();
    add_chords();
    for (int j = 0; j < n_; ++j) add_side_branch(static_cast<std::size_t>(j));
    link_junctions();
    return std::move(staged_);
  }

 private:
  // Each junction collects the ids of segments ending there (ins) and starting there (outs).
  struct Node {
    std::vector<std::int32_t> ins, outs;
  };

  void place_junctions() {
    const double ring_radius = rng_.uniform(22.0, 30.0);
    junction_.resize(static_cast<std::size_t>(n_));
    for (int j = 0; j < n_; ++j) {
      const double a = 2.0 * kPi * (j + rng_.uniform(-0.12, 0.12)) / n_;
      junction_[static_cast<std::size_t>(j)] = {ring_radius * std::cos(a), ring_radius * std::sin(a), rng_.uniform(-2.0, 2.0)};
    }
    nodes_.resize(static_cast<std::size_t>(n_));
  }

  double radius() { return rng_.uniform(1.0, 1.6); }

  std::int32_t stage(const std::string& name, const std::vector<Knot>& knots) {
    Network one(1.0);
    one.add(name, knots, {});
    VesselModel m = one.take();
    m.segments[0].id = next_id_++;
    staged_.segments.push_back(m.segments[0]);
    return staged_.segments.back().id;
  }

  // Ring segments, alternating direction so that some junctions are confluences.
  void add_ring() {
    for (int j = 0; j < n_; ++j) {
      const auto a = static_cast<std::size_t>(j);
      const auto b = static_cast<std::size_t>((j + 1) % n_);
      const bool forward = rng_.chance(0.6);
      const glm::dvec3 from = forward ? junction_[a] : junction_[b];
      const glm::dvec3 to = forward ? junction_[b] : junction_[a];
      glm::dvec3 mid = 0.5 * (from + to);
      mid += 0.15 * glm::length(mid) * glm::normalize(glm::dvec3(mid.x, mid.y, 0.0));
      const double r = radius();
      const std::int32_t id = stage("ring", {{from, r}, {mid, r}, {to, r}});
      nodes_[forward ? b : a].ins.push_back(id);
      nodes_[forward ? a : b].outs.push_back(id);
    }
  }

  // Chords from junction 0 to junctions 2..cycles, arching upwards at different heights.
  void add_chords() {
    for (int c = 0; c + 1 < cycles_; ++c) {
      const auto b = static_cast<std::size_t>(2 + c);
      const glm::dvec3 mid = 0.5 * (junction_[0] + junction_[b]) + glm::dvec3(0, 0, 8.0 + 7.0 * c);
      const double r = radius();
      const std::int32_t id = stage("chord", {{junction_[0], r}, {mid, r}, {junction_[b], r}});
      nodes_[0].outs.push_back(id);
      nodes_[b].ins.push_back(id);
    }
  }

  // One outward side branch at junction j (a child, or a parent if nothing starts there); some
  // split again into two free branches (a trifurcation when the junction had 3 ends).
  void add_side_branch(std::size_t j) {
    Node& node = nodes_[j];
    const glm::dvec3 p = junction_[j];
    const glm::dvec3 out = glm::normalize(glm::dvec3(p.x, p.y, 0.0) + glm::dvec3(0, 0, rng_.uniform(-8.0, 8.0)));
    const double r = radius();
    const double length = rng_.uniform(14.0, 22.0);
    if (node.ins.empty()) {
      node.ins.push_back(stage("feeder", {{p + length * out, r}, {p + 0.5 * length * out, r}, {p, r}}));
      return;
    }
    const std::int32_t id = stage("branch", {{p, r}, {p + 0.5 * length * out, r}, {p + length * out, r}});
    node.outs.push_back(id);
    if (!rng_.chance(0.5)) return;
    const glm::dvec3 tip = p + length * out;
    const glm::dvec3 up{0, 0, 1};
    for (double s : {-1.0, 1.0}) {
      const glm::dvec3 dir = glm::normalize(rotate(out, up, s * 0.6));
      const std::int32_t child = stage("twig", {{tip, 0.8 * r}, {tip + 6.0 * dir, 0.8 * r}, {tip + 12.0 * dir, 0.75 * r}});
      Segment& parent = staged_.segments[static_cast<std::size_t>(*staged_.index_of(id))];
      parent.children.push_back(child);
      staged_.segments.back().parents.push_back(id);
    }
  }

  // Every segment into a junction is a parent of every segment out of it.
  void link_junctions() {
    for (const Node& node : nodes_) {
      for (std::int32_t in : node.ins) {
        for (std::int32_t out : node.outs) {
          staged_.segments[static_cast<std::size_t>(*staged_.index_of(in))].children.push_back(out);
          staged_.segments[static_cast<std::size_t>(*staged_.index_of(out))].parents.push_back(in);
        }
      }
    }
  }

  Random rng_;
  int cycles_;
  int n_;  // ring segments
  std::vector<glm::dvec3> junction_;
  std::vector<Node> nodes_;
  VesselModel staged_;
  std::int32_t next_id_ = 1;
};

}  // namespace

std::vector<std::string> CaseGenerator::case_names() {
  return {"neuro", "neuro_aneurysm", "neuro_stenosis", "y_bifurcation"};
}

VesselModel CaseGenerator::make_case(const std::string& name) {
  if (name == "neuro") return neuro();
  if (name == "neuro_aneurysm") return neuro_aneurysm();
  if (name == "neuro_stenosis") return neuro_stenosis();
  if (name == "y_bifurcation") return y_bifurcation();
  return {};
}

VesselModel CaseGenerator::neuro() { return build_neuro({}, false); }
VesselModel CaseGenerator::neuro_aneurysm() {
  return build_neuro({.aneurysm = AneurysmSite::kMcaBifurcation, .dome_mm = 6.4, .neck_mm = 2.4}, false);
}
VesselModel CaseGenerator::neuro_stenosis() { return build_neuro({}, true); }
VesselModel CaseGenerator::neuro_variant(const NeuroMorphology& morphology) { return build_neuro(morphology, false); }

VesselModel CaseGenerator::y_bifurcation() {
  // A common-carotid-sized parent (r 3 mm, 60 mm) splitting symmetrically at 60 degrees into two
  // r 2.2 mm branches of 50 mm: the simplest steering task.
  Network net;
  const std::int32_t parent = net.add("parent", {{{0, 0, 0}, 3.0}, {{0, 0, 30}, 3.0}, {{0, 0, 60}, 3.0}}, {}, 400.0);
  const glm::dvec3 split = net.end(parent);
  const double a = 30.0 * kPi / 180.0;
  net.add("left_branch", {{split, 2.2}, {split + 25.0 * glm::dvec3(std::sin(a), 0, std::cos(a)), 2.2},
                          {split + 50.0 * glm::dvec3(std::sin(a), 0, std::cos(a)), 2.2}},
          {parent}, 200.0);
  net.add("right_branch", {{split, 2.2}, {split + 25.0 * glm::dvec3(-std::sin(a), 0, std::cos(a)), 2.2},
                           {split + 50.0 * glm::dvec3(-std::sin(a), 0, std::cos(a)), 2.2}},
          {parent}, 200.0);
  return net.take();
}

VesselModel CaseGenerator::random_tree(std::uint64_t seed, const RandomTreeOptions& options) {
  Random rng(seed);
  Network net(options.spacing_radii);
  struct Tip {
    std::int32_t id;
    glm::dvec3 dir;
    double radius;
  };
  const double r0 = options.root_radius_mm;
  const std::int32_t root = net.add("root", curved_path(rng, {0, 0, 0}, {0, 0, 1}, 10.0 * r0, r0, r0), {});
  std::vector<Tip> queue{{root, {0, 0, 1}, r0}};
  int count = 1;
  const double deg = kPi / 180.0;
  for (std::size_t q = 0; q < queue.size() && count < options.segments; ++q) {
    const Tip tip = queue[q];
    int children = rng.chance(options.trifurcation_chance) ? 3 : 2;
    children = std::min(children, options.segments - count);
    const double azimuth0 = rng.uniform(0.0, 2.0 * kPi);
    const glm::dvec3 side = any_perpendicular(tip.dir);
    for (int c = 0; c < children; ++c) {
      const double azimuth = azimuth0 + 2.0 * kPi * c / std::max(children, 2) + rng.uniform(-0.3, 0.3);
      const double angle = children == 1 ? 0.0
                                         : rng.uniform(options.min_branch_angle_deg, options.max_branch_angle_deg) * deg;
      const glm::dvec3 axis = rotate(side, tip.dir, azimuth);
      const glm::dvec3 dir = glm::normalize(rotate(tip.dir, axis, angle));
      const double r = std::max(0.4, tip.radius * std::pow(1.0 / children, 1.0 / 3.0) * rng.uniform(0.9, 1.05));
      const double length = r * rng.uniform(8.0, 14.0);
      const double r_end = r * rng.uniform(0.9, 1.0);
      const std::int32_t id =
          net.add("branch", curved_path(rng, net.end(tip.id), dir, length, std::min(r, tip.radius), r_end), {tip.id});
      queue.push_back({id, dir, r_end});
      ++count;
    }
  }
  return net.take();
}

VesselModel CaseGenerator::random_graph(std::uint64_t seed, int cycles) { return RandomGraphBuilder(seed, cycles).build(); }

VesselModel CaseGenerator::helix(double helix_radius_mm, double pitch_mm, double turns, double radius_mm, int points) {
  VesselModel model;
  Segment s;
  s.id = 1;
  s.name = "helix";
  for (int i = 0; i < points; ++i) {
    const double t = 2.0 * kPi * turns * i / (points - 1);
    s.points.push_back({{helix_radius_mm * std::cos(t), helix_radius_mm * std::sin(t), pitch_mm * t / (2.0 * kPi)},
                        radius_mm});
  }
  model.segments.push_back(std::move(s));
  return model;
}

}  // namespace cathbox::vessel
