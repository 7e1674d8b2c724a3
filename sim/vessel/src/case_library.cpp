#include "vessel/case_library.hpp"

#include <cstdio>
#include <iterator>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

namespace cathbox::vessel {
namespace {

// A 5F catheter (10 mm shaped tip) with a 0.014" wire (3 mm, 45 degree tip) inside: the
// diagnostic pair of the femoral cases. The cervical ICA cases use a 30 degree tip; the arch cases
// a 90 degree (Headhunter-style) one, which can be turned along the arch past the left subclavian
// and hooked into a great vessel on the pull back (a 30 degree tip follows the outer curve into
// the left subclavian whichever way it is turned).
std::string catheter_and_wire(int tip_curve_deg) {
  return R"(tool catheter catheter
  section 960 od=1.67 ei=250 gj=190
  section 30 od=1.67 ei=40 gj=30
  section 10 od=1.67 ei=20 gj=15 curve=)" +
         std::to_string(tip_curve_deg) + R"(
  friction 0.15
  inner_diameter 1.0
end

tool guidewire guidewire
  section 1750 od=0.36 ei=40 gj=31
  section 35 od=0.36 ei=3 gj=2.3
  section 12 od=0.36 ei=0.3 gj=0.23
  section 3 od=0.36 ei=0.3 gj=0.23 curve=45
  friction 0.08
  inside catheter
end
)";
}

// 6F guide > microcatheter (60 degree steam-shaped tip) > 0.014" microwire (6 mm, 90 degree
// tip): the intracranial stack of the aneurysm cases (as cases/neuro_coiling.case).
constexpr const char* kGuideStack = R"(tool guide catheter
  section 900 od=2.0 ei=300 gj=230
  section 80 od=2.0 ei=60 gj=45
  friction 0.15
  inner_diameter 1.8
end

tool microcatheter catheter
  section 1350 od=0.8 ei=8 gj=6
  section 120 od=0.75 ei=3 gj=2.4
  section 25 od=0.7 ei=1 gj=0.8
  section 5 od=0.7 ei=1 gj=0.8 curve=60
  friction 0.1
  inner_diameter 0.43
  inside guide
  spacing 2 0.5 40
end

tool microwire guidewire
  section 1750 od=0.36 ei=40 gj=31
  section 35 od=0.36 ei=3 gj=2.3
  section 9 od=0.36 ei=0.3 gj=0.23
  section 6 od=0.36 ei=0.3 gj=0.23 curve=90
  friction 0.08
  inside microcatheter
end
)";

// Arch cases: from the descending aorta over the arch into the left common carotid.
// `hook_mm`: the catheter's insertion, pulled back to from over the arch, at which its tip (turned
// up) drops into the target's origin for this arch, so that the wire leaves it without its tip
// catching on the wall and snapping free (library_feel_test.cpp: no tool's force changes by more
// than the box's slew); `advance_mm_s`: the catheter's speed up the descending aorta.
// `lead`: the script from the wire's lead out of the hooked catheter on (9 s), where a morphology
// needs its own; empty, the wire is led at 15 mm/s to 70 mm past the hook.
LibraryCase arch_case(const std::string& name, const std::string& title, ArchType type, int hook_mm,
                      int advance_mm_s, const std::string& about, const std::string& lead = "") {
  LibraryCase c;
  c.name = name;
  c.title = title;
  c.about = about +
            "# Entry: the descending aorta (femoral approach); target: the left common carotid, 30 % up.\n"
            "# Tools: 5F catheter with a 90 degree tip and a 0.014\" wire with a 45 degree tip.\n";
  c.morphology.arch = type;
  c.entry_segment = "descending_aorta";
  c.entry_fraction = 0.6;
  c.entry_upstream = true;
  c.target_segment = "left_common_carotid";
  c.target_fraction = 0.3;
  c.tools = catheter_and_wire(90);
  c.actions =
      "# The catheter, its tip turned a quarter turn, leads the wire up the descending aorta past the\n"
      "# left subclavian and over the arch; then, the wire drawn back inside and the tip turned up, it\n"
      "# is pulled back slowly until the tip drops into the target's origin, and the wire is advanced\n"
      "# out of it into the left common carotid" + std::string(lead.empty() ? ".\n" : " (below).\n") +
      "0      select catheter\n"
      "0      rotate_to 90 at 360\n"
      "0      insert_to 130 at " + std::to_string(advance_mm_s) + "\n"
      "0      select guidewire\n"
      "0      insert_to 120 at 30\n"
      "4500   insert_to " + std::to_string(hook_mm - 15) + " at 30\n"
      "4500   select catheter\n"
      "4500   rotate_to 0 at 180\n"
      "5500   insert_to " + std::to_string(hook_mm) + " at 10\n" +
      (lead.empty() ? "9000   select guidewire\n"
                      "9000   insert_to " + std::to_string(hook_mm + 70) + " at 15\n"
                      "14000  end\n"
                    : lead);
  return c;
}

LibraryCase ica_case(const std::string& name, const std::string& title, IcaTortuosity t, const std::string& about) {
  LibraryCase c;
  c.name = name;
  c.title = title;
  c.about = about +
            "# Entry: the left common carotid, 80 % up; target: the left ICA at the skull base (its\n"
            "# cervical part passed). Tools: 5F catheter (30 degree tip), 0.014\" wire (45 degree tip).\n";
  c.morphology.left_ica = t;
  c.entry_segment = "left_common_carotid";
  c.entry_fraction = 0.8;
  c.target_segment = "left_internal_carotid";
  c.target_fraction = t == IcaTortuosity::kCoiled ? 0.45 : 0.35;
  c.tools = catheter_and_wire(30);
  c.actions =
      "# The wire leads out of the catheter, past the carotid bifurcation into the ICA and\n"
      "# through its cervical curves to the skull base; the catheter stays in the common carotid.\n"
      "0     select guidewire\n"
      "0     insert_to 115 at 15\n"
      "8000  end\n";
  return c;
}

LibraryCase aneurysm_case(const std::string& name, const std::string& title, AneurysmSite site, double dome_mm,
                          double neck_mm, const std::string& entry, double entry_fraction, const std::string& sac,
                          const std::string& about, const std::string& actions) {
  LibraryCase c;
  c.name = name;
  c.title = title;
  char sizes[160];
  std::snprintf(sizes, sizeof sizes, "# Sac: %.1f mm dome, %.1f mm neck (dome/neck %.1f); target: the neck.\n", dome_mm, neck_mm,
                dome_mm / neck_mm);
  c.about = about + sizes +
            "# Tools: 6F guide parked in the parent artery > microcatheter (60 degree tip) > 0.014\"\n"
            "# microwire (90 degree tip), as cases/neuro_coiling.case.\n";
  c.morphology.aneurysm = site;
  c.morphology.dome_mm = dome_mm;
  c.morphology.neck_mm = neck_mm;
  c.entry_segment = entry;
  c.entry_fraction = entry_fraction;
  c.target_segment = sac;
  c.target_fraction = 0.05;
  c.tools = kGuideStack;
  c.actions = actions;
  return c;
}

std::vector<LibraryCase> arch_cases() {
  const std::string arch_ref = "# Arch types: Madhwal et al. 2008; bovine arch: Layton et al. AJNR 2006.\n";
  return {
      arch_case("arch_type1", "library: type I aortic arch", ArchType::kTypeI, 87, 30,
                "# Type I arch: the great vessels arise from the top of the arch (brachiocephalic origin\n"
                "# 5.4 mm = 0.8 common carotid diameters below it).\n" + arch_ref),
      arch_case("arch_type2", "library: type II aortic arch", ArchType::kTypeII, 90, 30,
                "# Type II arch: the brachiocephalic origin 10.5 mm = 1.6 CCA diameters below the top.\n" + arch_ref),
      arch_case("arch_type3", "library: type III aortic arch", ArchType::kTypeIII, 91, 20,
                "# Type III arch: the brachiocephalic origin 13.5 mm = 2.1 CCA diameters below the top.\n" + arch_ref),
      arch_case("arch_bovine", "library: bovine aortic arch", ArchType::kBovine, 102, 30,
                "# Bovine arch (type I shape): the left common carotid arises from the brachiocephalic\n"
                "# trunk, 16 mm above the arch.\n" + arch_ref,
                "# The wire is led out of the hook 15.5 mm into the left common carotid at 10 mm/s and stopped\n"
                "# short of the node crossing where its second free node, pressed on the wall past the hooked\n"
                "# tip, snapped off at 118.1 mm (led on at 15 mm/s: 4 ticks over the box's 100 mN slew). Catheter\n"
                "# and wire then go on together 5 mm at 5 mm/s, so the catheter's tip comes into the carotid's\n"
                "# origin over the wire, coaxial, and the wire goes on out of it at 5 mm/s to the target.\n"
                "# Stopped at 117-118 mm it reaches with no tick over the slew (116 or 118.5 mm: 1 tick); the\n"
                "# window is the wire's length out of the hook, 15-16 mm (docs/sim-tool/convergence.md).\n"
                "9000   select guidewire\n9000   insert_to 117.5 at 10\n12250  select catheter\n"
                "12250  insert_to 107 at 5\n12250  select guidewire\n12250  insert_to 122.5 at 5\n"
                "13450  insert_to 172 at 5\n26350  end\n"),
  };
}

std::vector<LibraryCase> ica_cases() {
  const std::string ica_ref = "# Grades: Weibel and Fields, Neurology 1965.\n";
  return {
      ica_case("ica_straight", "library: straight cervical ICA", IcaTortuosity::kStraight,
               "# Cervical left ICA without tortuosity (the reference).\n" + ica_ref),
      ica_case("ica_tortuous", "library: tortuous cervical ICA", IcaTortuosity::kTortuous,
               "# Cervical left ICA with an S-shaped elongation (Weibel-Fields tortuosity).\n" + ica_ref),
      ica_case("ica_coil", "library: coiled cervical ICA", IcaTortuosity::kCoiled,
               "# Cervical left ICA with a full loop (Weibel-Fields coiling).\n" + ica_ref),
      ica_case("ica_kink", "library: kinked cervical ICA", IcaTortuosity::kKinked,
               "# Cervical left ICA with an acute (83 degree) angle between two limbs (Weibel-Fields kinking),\n"
               "# its apex rounded at 5 mm (two lumen radii: a tighter bend folds the wall).\n" + ica_ref),
  };
}

std::vector<LibraryCase> aneurysm_cases() {
  const std::string sac_ref = "# Sizes and sites: UCAS (NEJM 2012), ISUIA (Lancet 2003).\n";
  return {
      aneurysm_case("aneurysm_mca", "library: right MCA bifurcation aneurysm", AneurysmSite::kMcaBifurcation, 6.4, 2.4,
                    "right_internal_carotid", 0.12, "right_mca_aneurysm",
                    "# Saccular aneurysm at the right MCA bifurcation; guide in the right ICA.\n" + sac_ref,
                    "# The microwire is led 8 mm out of the microcatheter's tip while both sit at the guide's tip\n"
                    "# in the straight cervical ICA, where the guide holds the microcatheter coaxial: it comes out\n"
                    "# touching no wall (led out of a curved microcatheter parked anywhere up the ICA, its tip on\n"
                    "# the wall, each node crossing the tip jumped 500-1000 mN). The two go up as a unit at\n"
                    "# 20 mm/s, the wire's tip (turned 135 degrees) 8 mm ahead through the siphon and the terminus\n"
                    "# into the M1. With the microcatheter at 125 mm the wire is drawn back 3 mm inside it, and the\n"
                    "# microcatheter goes on alone at 4 mm/s, turned to 90 degrees to lift its tip off the M1's\n"
                    "# floor into the neck (unturned it passes 1.6-1.8 mm below the target). Stopped at 120-130 mm,\n"
                    "# the wire 1-6 mm inside, the last push at 3-6 mm/s, the unit at 10-20 mm/s, the wire turned\n"
                    "# 135-180 degrees and 8-10 mm ahead: all reach with no tick over the box's 100 mN slew.\n"
                    "0      select microcatheter\n0      rotate_to 180 at 720\n0      select microwire\n"
                    "0      rotate_to 135 at 720\n1200   insert_to 8 at 4\n3500   insert_to 133 at 20\n"
                    "3500   select microcatheter\n3500   insert_to 125 at 20\n9950   select microwire\n"
                    "9950   insert_to 122 at 4\n12900  select microcatheter\n12900  rotate_to 90 at 360\n"
                    "12900  insert_to 160 at 4\n21900  end\n"),
      aneurysm_case("aneurysm_pcom", "library: left PCom aneurysm", AneurysmSite::kPcom, 6.0, 3.0,
                    "left_internal_carotid", 0.12, "left_pcom_aneurysm",
                    "# Saccular aneurysm of the left ICA at the posterior communicating origin; guide in the\n"
                    "# left ICA.\n" + sac_ref,
                    "# The wire stays 4 mm inside the microcatheter as that goes to 108 mm, then leads at 3 mm/s,\n"
                    "# the microcatheter following at 5: leaving the tip at 20 mm/s, pressed on the wall, its\n"
                    "# force swung by 420 mN a tick (library_feel_test.cpp).\n"
                    "0      select microcatheter\n0      insert_to 22 at 20\n0      select microwire\n"
                    "0      insert_to 40 at 20\n1000   insert_to 104 at 20\n1000   select microcatheter\n"
                    "1000   insert_to 108 at 20\n5500   select microwire\n5500   insert_to 150 at 3\n"
                    "6000   select microcatheter\n6000   insert_to 142 at 5\n16000  end\n"),
      aneurysm_case("aneurysm_acom", "library: ACom aneurysm", AneurysmSite::kAcom, 5.0, 2.2, "left_internal_carotid", 0.12,
                    "acom_aneurysm",
                    "# Saccular aneurysm of the anterior communicating artery; guide in the left ICA, the\n"
                    "# approach through the left A1.\n" + sac_ref,
                    "# Past the PCom origin, the microcatheter and the microwire are turned 145 degrees at the\n"
                    "# ICA terminus so that their tips point into the left A1 (untouched, the wire takes the M1).\n"
                    "# The wire stays in the microcatheter until then: out of its tip at 20 mm/s, pressed on\n"
                    "# the wall, its force swung by up to 1.3 N a tick (library_feel_test.cpp).\n"
                    "0      select microcatheter\n0      insert_to 22 at 20\n0      select microwire\n"
                    "0      insert_to 40 at 20\n1000   insert_to 104 at 20\n1000   select microcatheter\n"
                    "1000   insert_to 108 at 20\n5500   rotate_to 145 at 180\n5500   select microwire\n"
                    "5500   rotate_to 145 at 180\n7000   insert_to 175 at 10\n7500   select microcatheter\n"
                    "7500   insert_to 165 at 10\n14000  end\n"),
      aneurysm_case("aneurysm_basilar", "library: basilar tip aneurysm", AneurysmSite::kBasilarTip, 8.0, 4.0,
                    "left_vertebral", 0.5, "basilar_tip_aneurysm",
                    "# Wide-necked saccular aneurysm at the basilar tip; guide in the left vertebral (V2).\n" + sac_ref,
                    "# The wire leads at 5 mm/s: at 10 it jammed 15 mm out of the microcatheter as that\n"
                    "# followed (tests/host/session/data/basilar_wire_jammed.actions).\n"
                    "0      select microcatheter\n0      insert_to 22 at 20\n0      select microwire\n"
                    "0      insert_to 40 at 20\n1000   insert_to 110 at 20\n1000   select microcatheter\n"
                    "1000   insert_to 100 at 20\n6000   select microwire\n6000   insert_to 128 at 5\n"
                    "6500   select microcatheter\n6500   insert_to 122 at 10\n11000  end\n"),
  };
}

// The library in its order: arches, cervical ICAs, aneurysms.
std::vector<LibraryCase> all_cases() {
  std::vector<LibraryCase> all = arch_cases();
  for (std::vector<LibraryCase> part : {ica_cases(), aneurysm_cases()}) {
    all.insert(all.end(), std::make_move_iterator(part.begin()), std::make_move_iterator(part.end()));
  }
  return all;
}

}  // namespace

std::vector<std::string> library_case_names() {
  std::vector<std::string> names;
  for (const LibraryCase& c : all_cases()) names.push_back(c.name);
  return names;
}

std::optional<LibraryCase> library_case(const std::string& name) {
  for (LibraryCase& c : all_cases()) {
    if (c.name == name) return std::move(c);
  }
  return std::nullopt;
}

VesselModel library_model(const LibraryCase& c) { return CaseGenerator::neuro_variant(c.morphology); }

std::string library_case_text(const LibraryCase& c, const VesselModel& model) {
  const auto find = [&](const std::string& name) -> const Segment* {
    for (const Segment& s : model.segments) {
      if (s.name == name) return &s;
    }
    return nullptr;
  };
  const Segment* entry = find(c.entry_segment);
  const Segment* target = find(c.target_segment);
  if (entry == nullptr || target == nullptr || entry->points.size() < 2) return {};
  // The entry point: the centerline point nearest entry_fraction of the segment's arc length,
  // heading along the centerline.
  std::vector<double> arc{0.0};
  for (std::size_t i = 1; i < entry->points.size(); ++i) {
    arc.push_back(arc.back() + glm::length(entry->points[i].pos_mm - entry->points[i - 1].pos_mm));
  }
  std::size_t i = 0;
  while (i + 2 < arc.size() && arc[i + 1] <= c.entry_fraction * arc.back()) ++i;
  const glm::dvec3 p = entry->points[i].pos_mm;
  const glm::dvec3 along = glm::normalize(entry->points[i + 1].pos_mm - p);
  const glm::dvec3 d = c.entry_upstream ? -along : along;
  char line[256];
  std::string text = "# " + c.title + " (generated: cathbox case generate " + c.name + " -o DIR)\n" + c.about;
  text += "cathbox-case 1\nname " + c.title + "\nvessel " + c.name + ".hclm\n";
  std::snprintf(line, sizeof line, "entry %.2f %.2f %.2f  %.4f %.4f %.4f\n", p.x, p.y, p.z, d.x, d.y, d.z);
  text += line;
  std::snprintf(line, sizeof line, "target %d %.2f\n\n", target->id, c.target_fraction);
  text += line;
  return text + c.tools;
}

}  // namespace cathbox::vessel
