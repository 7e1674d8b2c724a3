#include "neuro_case.hpp"
#include "neuro_shapes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>

namespace cathbox::vessel::detail {
namespace {

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

[[nodiscard]] glm::dvec3 mirror(const glm::dvec3& p) { return {-p.x, p.y, p.z}; }

// build_neuro's steps, in the order the segments are added (their ids follow that order): the
// aorta, the arch's branches up to the carotid bifurcations, each carotid side, the
// vertebrobasilar system, each posterior cerebral side, the anterior communicating complex.
class NeuroBuilder {
 public:
  NeuroBuilder(const NeuroMorphology& m, bool stenosed)
      : m_(m),
        stenosed_(stenosed),
        shape_(arch_shape(m.arch)),
        bovine_(m.arch == ArchType::kBovine),
        arch_center_{0, 0, 18.0 - shape_.height_mm} {}

  VesselModel build() {
    add_aorta();
    add_arch_branches();
    const Side right = add_carotid_side(false, rcca_);
    const Side left = add_carotid_side(true, lcca_);
    add_vertebrobasilar();
    add_posterior_side(false, right);
    add_posterior_side(true, left);
    add_anterior_communicating(right, left);
    return net_.take();
  }

 private:
  // What one carotid side leaves for the circle of Willis.
  struct Side {
    std::int32_t ica_top = 0;   // supraclinoid ICA ending at the PComm origin
    std::int32_t ica_term = 0;  // ICA terminal segment
    std::int32_t m1 = 0;
    std::int32_t a1 = 0;
  };

  static constexpr double kArchRadius = 30.0;

  // Aortic arch [1]: the ascending aorta rises on the right and in front, the arch (a half
  // circle of ~30 mm centreline radius in an oblique plane) passes over to the left and back, and
  // the descending aorta goes down. Liberty: the three branch origins are 40 degrees (~21 mm)
  // apart along the arch (often closer in vivo) so each junction has room for its rings.
  [[nodiscard]] glm::dvec3 arch(double deg) const {
    const double a = deg * std::numbers::pi / 180.0;
    return arch_center_ + kArchRadius * (std::cos(a) * anterior_ + (shape_.height_mm / kArchRadius) * std::sin(a) * up_);
  }
  [[nodiscard]] glm::dvec3 arch_normal(double deg) const {
    const double a = deg * std::numbers::pi / 180.0;
    const glm::dvec3 n = std::cos(a) * (shape_.height_mm / kArchRadius) * anterior_ + std::sin(a) * up_;
    return shape_.height_mm == kArchRadius ? n : glm::normalize(n);
  }
  [[nodiscard]] static double mid(double a, double b) { return std::round(0.5 * (a + b)); }
  // A point of the left side as given, of the right side mirrored.
  [[nodiscard]] static glm::dvec3 side_point(bool left, double x, double y, double z) {
    return left ? glm::dvec3(x, y, z) : mirror({x, y, z});
  }

  // The ascending aorta, the arch (one segment between branch origins; a bovine arch has no
  // separate left carotid origin) and the descending aorta.
  void add_aorta() {
    const double bct_deg = shape_.bct_deg;
    const double lcca_deg = shape_.lcca_deg;
    const double lsa_deg = shape_.lsa_deg;
    arch1_ = net_.add("ascending_aorta",
                      {{arch(0) - 60.0 * up_, 15.0}, {arch(0) - 30.0 * up_, 14.5}, {arch(0), 14.0},
                       {arch(mid(0, bct_deg)), 13.7}, {arch(bct_deg), 13.5}},
                      {}, 5000.0);
    arch2_ = bovine_ ? net_.add("aortic_arch_1",
                                {{arch(bct_deg), 13.5}, {arch(75), 13.2}, {arch(95), 13.0}, {arch(115), 12.7}, {arch(lsa_deg), 12.5}},
                                {arch1_}, 4200.0)
                     : net_.add("aortic_arch_1", {{arch(bct_deg), 13.5}, {arch(mid(bct_deg, lcca_deg)), 13.2}, {arch(lcca_deg), 13.0}},
                                {arch1_}, 4200.0);
    arch3_ = bovine_ ? arch2_
                     : net_.add("aortic_arch_2", {{arch(lcca_deg), 13.0}, {arch(mid(lcca_deg, lsa_deg)), 12.7}, {arch(lsa_deg), 12.5}},
                                {arch2_}, 3800.0);
    net_.add("descending_aorta",
             {{arch(lsa_deg), 12.5}, {arch(mid(lsa_deg, 180.0)), 12.2}, {arch(180), 12.0}, {arch(180) - 30.0 * up_, 11.8},
              {arch(180) - 70.0 * up_, 11.5}},
             {arch3_}, 3400.0);
  }

  // The brachiocephalic trunk, both subclavian arteries and both common carotids.
  void add_arch_branches() {
    const double bct_deg = shape_.bct_deg;
    const double lsa_deg = shape_.lsa_deg;
    // Brachiocephalic trunk [2]: ~45 mm up and to the right, 12 mm wide.
    // On a high arch (types II, III) the trunk leaves the ascending limb tilted upwards.
    const glm::dvec3 bct_direction =
        shape_.height_mm == kArchRadius ? arch_normal(bct_deg) : glm::normalize(arch_normal(bct_deg) + 0.8 * up_);
    // Bovine arch [12]: the left common carotid shares the brachiocephalic origin (the common
    // trunk splits 16 mm above the arch).
    const std::int32_t bct_stem =
        bovine_ ? net_.add("brachiocephalic_trunk",
                           {{arch(bct_deg), 6.2}, {arch(bct_deg) + 8.0 * arch_normal(bct_deg), 6.1},
                            {arch(bct_deg) + 16.0 * arch_normal(bct_deg), 6.0}},
                           {arch1_}, 1220.0)
                : 0;
    const std::int32_t bct =
        bovine_ ? net_.add("brachiocephalic_trunk_2", {{net_.end(bct_stem), 5.9}, {{-13, 24, 38}, 5.9}, {{-17, 22, 50}, 5.8}},
                           {bct_stem}, 800.0)
                : net_.add("brachiocephalic_trunk",
                           {{arch(bct_deg), 6.2}, {arch(bct_deg) + 16.0 * bct_direction, 6.0}, {{-13, 24, 38}, 5.9},
                            {{-17, 22, 50}, 5.8}},
                           {arch1_}, 800.0);
    // Subclavian arteries [2] (~9 mm) with the vertebral arteries arising from their first part.
    rsub1_ = net_.add("right_subclavian_1", {{net_.end(bct), 4.6}, {{-28, 16, 56}, 4.5}, {{-40, 10, 58}, 4.4}}, {bct}, 350.0);
    net_.add("right_subclavian_2", {{net_.end(rsub1_), 4.4}, {{-55, 6, 56}, 4.2}, {{-75, 4, 48}, 4.0}}, {rsub1_}, 250.0);
    lsub1_ = net_.add("left_subclavian_1",
                      {{arch(lsa_deg), 5.0}, {arch(lsa_deg) + 16.0 * arch_normal(lsa_deg), 4.8}, {{22, -30, 40}, 4.6},
                       {{40, -20, 56}, 4.4}},
                      {arch3_}, 350.0);
    net_.add("left_subclavian_2", {{net_.end(lsub1_), 4.4}, {{55, -16, 55}, 4.2}, {{75, -12, 46}, 4.0}}, {lsub1_}, 250.0);

    // Common carotid arteries [3] (6.4 mm) up to the bifurcation at about C4.
    rcca_ = net_.add("right_common_carotid",
                     {{net_.end(bct), 3.3}, {{-20, 18, 75}, 3.25}, {{-24, 17, 100}, 3.2}, {{-26, 16, 125}, 3.2}}, {bct}, 420.0);
    lcca_ = bovine_ ? net_.add("left_common_carotid",
                               {{net_.end(bct_stem), 3.4}, {{0, 18, 42}, 3.35}, {{12, 10, 62}, 3.3}, {{18, 9, 80}, 3.25},
                                {{22, 12, 100}, 3.2}, {{26, 16, 125}, 3.2}},
                               {bct_stem}, 420.0)
                    : net_.add("left_common_carotid",
                               {{net_.end(arch2_), 3.4}, {net_.end(arch2_) + 14.0 * arch_normal(shape_.lcca_deg), 3.35},
                                {{8, -2, 50}, 3.3}, {{16, 6, 75}, 3.25}, {{22, 12, 100}, 3.2}, {{26, 16, 125}, 3.2}},
                               {arch2_}, 420.0);
  }

  // One side's carotid tree from the common carotid bifurcation: external carotid, internal
  // carotid, M1 with its two M2 trunks, the side's aneurysm if any, A1.
  Side add_carotid_side(bool left, std::int32_t cca) {
    const auto P = [left](double x, double y, double z) { return side_point(left, x, y, z); };
    const std::string side = left ? "left_" : "right_";
    // External carotid (~4 mm), anteromedial, ending in the face.
    net_.add(side + "external_carotid", {{net_.end(cca), 2.1}, {P(24, 22, 140), 2.0}, {P(28, 30, 160), 1.8}}, {cca}, 150.0);
    const std::int32_t ica = add_internal_carotid(left, cca);
    Side s;
    s.ica_top = ica;
    s.ica_term = net_.add(side + "internal_carotid_terminal", {{net_.end(ica), 1.9}, {P(14, 14, 231), 1.85}, {P(14, 15, 236), 1.8}},
                          {ica}, 220.0);
    // M1 [5]: ~16 mm laterally, 2.8 mm.
    s.m1 = net_.add(side + "middle_cerebral_m1", {{net_.end(s.ica_term), 1.45}, {P(22, 16, 237), 1.4}, {P(31, 16, 239), 1.35}},
                    {s.ica_term}, 130.0);
    const std::int32_t m1 = s.m1;
    net_.add(side + "middle_cerebral_m2_superior", {{net_.end(m1), 1.05}, {P(34, 18, 249), 1.0}, {P(40, 21, 262), 0.95}},
             {m1}, 65.0);
    net_.add(side + "middle_cerebral_m2_inferior", {{net_.end(m1), 1.05}, {P(35, 13, 230), 1.0}, {P(44, 9, 222), 0.95}},
             {m1}, 65.0);
    if (!left && m_.aneurysm == AneurysmSite::kMcaBifurcation) {
      // [9] Saccular aneurysm at the (right) MCA bifurcation, pointing along the M1 axis.
      const glm::dvec3 base = net_.end(m1);
      net_.add(side + "mca_aneurysm", sac_knots(m_, base, glm::normalize(base - P(22, 16, 237))), {m1}, 0.0,
               nullptr, 0.35);
    }
    if (left && m_.aneurysm == AneurysmSite::kPcom) {
      // [9][14] Left posterior communicating aneurysm: from the ICA wall at the PComm origin,
      // pointing posterolaterally and down (the usual projection).
      net_.add(side + "pcom_aneurysm", sac_knots(m_, net_.end(ica), glm::normalize(glm::dvec3(1.0, -0.5, -0.35))),
               {ica}, 0.0, nullptr, 0.35);
    }
    // A1 [6]: ~13 mm medially and anteriorly, 2.3 mm; ends at the AComm.
    s.a1 = net_.add(side + "anterior_cerebral_a1", {{net_.end(s.ica_term), 1.2}, {P(9, 20, 238), 1.15}, {P(3, 27, 240), 1.1}},
                    {s.ica_term}, 70.0);
    return s;
  }

  // Internal carotid [3][4]: carotid bulb (dilated origin), cervical ascent to the skull base,
  // petrous segment turning anteromedially, cavernous siphon (S curve: posterior bend, anterior
  // genu), clinoid/ophthalmic segment turning back up to the PComm origin.
  std::int32_t add_internal_carotid(bool left, std::int32_t cca) {
    const auto P = [left](double x, double y, double z) { return side_point(left, x, y, z); };
    RadiusProfile profile = nullptr;
    if (left && stenosed_) profile = stenosis(12.0, 4.0, 0.7);  // [10] 70 % at the bulb
    std::vector<Knot> ica_knots{{net_.end(cca), 3.0}};
    for (const Knot& k : cervical_ica(left ? m_.left_ica : IcaTortuosity::kStraight)) ica_knots.push_back({P(k.pos_mm.x, k.pos_mm.y, k.pos_mm.z), k.radius_mm});
    for (const Knot& k : std::vector<Knot>{{P(26, 10, 185), 2.35}, {P(22, 16, 196), 2.3}, {P(18, 24, 200), 2.25},
                                           {P(17, 30, 206), 2.2}, {P(16, 33, 214), 2.1}, {P(15, 28, 222), 2.0},
                                           {P(14, 14, 226), 1.95}}) {
      ica_knots.push_back(k);
    }
    return net_.add(std::string(left ? "left_" : "right_") + "internal_carotid", ica_knots, {cca}, 250.0, profile);
  }

  // Vertebral arteries [2][8] (~3.6 mm): V1 up to C6, V2 through the transverse foramina, V3
  // loop behind the atlas, V4 through the foramen magnum to the vertebrobasilar junction; the
  // basilar artery [8] (~32 mm along the clivus, 3.2 mm) as their confluence, and its tip
  // aneurysm if any.
  void add_vertebrobasilar() {
    const glm::dvec3 vb_junction{0, -6, 200};
    const auto vertebral = [&](bool left_side, std::int32_t subclavian) {
      const auto P = [left_side](double x, double y, double z) { return side_point(left_side, x, y, z); };
      return net_.add(std::string(left_side ? "left_" : "right_") + "vertebral",
                      {{net_.end(subclavian), 1.9}, {P(38, -8, 80), 1.85}, {P(30, -12, 110), 1.8}, {P(28, -14, 150), 1.8},
                       {P(30, -18, 168), 1.75}, {P(26, -26, 178), 1.7}, {P(14, -20, 186), 1.65}, {P(6, -11, 194), 1.6},
                       {vb_junction, 1.6}},
                      {subclavian}, 100.0);
    };
    const std::int32_t rva = vertebral(false, rsub1_);
    const std::int32_t lva = vertebral(true, lsub1_);
    basilar_ = net_.add("basilar", {{vb_junction, 1.65}, {{0, -3, 215}, 1.6}, {{0, -1, 232}, 1.55}}, {lva, rva}, 190.0);
    if (m_.aneurysm == AneurysmSite::kBasilarTip) {
      // [9][14] Basilar tip aneurysm: along the basilar axis, between the two P1 origins.
      net_.add("basilar_tip_aneurysm", sac_knots(m_, net_.end(basilar_), glm::normalize(glm::dvec3(0, 0.12, 1))),
               {basilar_}, 0.0, nullptr, 0.35);
    }
  }

  // P1 [7]: ~7 mm, 2.1 mm; PComm [7] joins at the P1/P2 junction; P2 runs around the midbrain.
  void add_posterior_side(bool left_side, const Side& s) {
    const auto P = [left_side](double x, double y, double z) { return side_point(left_side, x, y, z); };
    const std::string side = left_side ? "left_" : "right_";
    const std::int32_t p1 = net_.add(side + "posterior_cerebral_p1", {{net_.end(basilar_), 1.05}, {P(4, -1, 233), 1.05},
                                                                       {P(9, 0, 235), 1.0}},
                                     {basilar_}, 45.0);
    const std::int32_t p2 = net_.add(side + "posterior_cerebral_p2",
                                     {{net_.end(p1), 1.0}, {P(17, -8, 238), 0.95}, {P(24, -22, 242), 0.95}, {P(28, -40, 246), 0.9}},
                                     {p1}, 50.0);
    // PComm [7]: from the ICA (at the end of the supraclinoid segment) back to the P1/P2 junction.
    net_.add_link(side + "posterior_communicating", s.ica_top, {P(12, 7, 230)}, net_.end(p1), 0.7, {p2});
  }

  // A2 and the anterior communicating artery [6]. Liberty: the AComm is 6 mm (range 0.3-7 mm)
  // so both A1/A2 junctions have room.
  void add_anterior_communicating(const Side& right, const Side& left) {
    const std::int32_t a2_right = net_.add("right_anterior_cerebral_a2",
                                           {{net_.end(right.a1), 1.1}, {{-3.5, 33, 252}, 1.05}, {{-3.5, 40, 270}, 1.0}},
                                           {right.a1}, 60.0);
    net_.add("left_anterior_cerebral_a2", {{net_.end(left.a1), 1.1}, {{3.5, 33, 252}, 1.05}, {{3.5, 40, 270}, 1.0}},
             {left.a1}, 60.0);
    if (m_.aneurysm == AneurysmSite::kAcom) {
      // [9][14] Anterior communicating aneurysm: from the middle of the AComm, pointing
      // anteriorly and up; the AComm is split there.
      const std::int32_t acomm =
          net_.add("anterior_communicating", {{net_.end(left.a1), 0.75}, {{0, 28.5, 241}, 0.75}}, {left.a1});
      net_.add("acom_aneurysm", sac_knots(m_, net_.end(acomm), glm::normalize(glm::dvec3(0, 0.7, 0.7))),
               {acomm}, 0.0, nullptr, 0.35);
      net_.add_link("anterior_communicating_2", acomm, {}, net_.end(right.a1), 0.75, {a2_right});
    } else {
      net_.add_link("anterior_communicating", left.a1, {{0, 28.5, 241}}, net_.end(right.a1), 0.75, {a2_right});
    }
  }

  const NeuroMorphology& m_;
  bool stenosed_;
  ArchShape shape_;
  bool bovine_;
  glm::dvec3 arch_center_;
  glm::dvec3 anterior_ = glm::normalize(glm::dvec3(-0.35, 1.0, 0.0));
  glm::dvec3 up_{0, 0, 1};
  Network net_;
  std::int32_t arch1_ = 0, arch2_ = 0, arch3_ = 0;  // the arch's segments (arch3_ == arch2_ on a bovine arch)
  std::int32_t rsub1_ = 0, lsub1_ = 0;              // the subclavians' first parts
  std::int32_t rcca_ = 0, lcca_ = 0;                // the common carotids
  std::int32_t basilar_ = 0;
};

}  // namespace

VesselModel build_neuro(const NeuroMorphology& m, bool stenosed) { return NeuroBuilder(m, stenosed).build(); }

}  // namespace cathbox::vessel::detail
