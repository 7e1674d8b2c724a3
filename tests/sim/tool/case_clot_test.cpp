// The case file's `clot` statement and a catheter's `aspiration` line, resolved against the
// vessel model and run through the flow model (the bundled thrombectomy cases).
#include <gtest/gtest.h>

#include <string>

#include "flow/flow_network.hpp"
#include "flow/reperfusion.hpp"
#include "scenario/case_clots.hpp"
#include "scenario/case_file.hpp"
#include "vessel/hclm.hpp"

namespace cathbox::tool {
namespace {

std::string source(const std::string& relative) { return std::string(CATHBOX_SOURCE_DIR) + "/" + relative; }

// A catheter in the aspiration catheter is steered by what it carries while advanced, a stent
// retriever's push wire too (the Solumbra stacks' microcatheter, since record format 36: unsteered,
// the M1 run's left its wire at the M1's junction; docs/sim-tool/convergence.md, "The lumen's
// bending push from the change of the moment"); not a tool outside the aspiration catheter.
TEST(CaseClot, ACatheterCarryingAStentRetrieverIsSteeredWhileAdvancedInTheAspirationCatheter) {
  const CaseParse p = parse_case(
      "vessel neuro.hclm\n"
      "tool guide catheter\n"
      "  section 900 od=2.7 ei=400 gj=300\n"
      "  inner_diameter 2.13\n"
      "end\n"
      "tool asp catheter\n"
      "  section 1300 od=2.1 ei=30 gj=23\n"
      "  inner_diameter 1.73\n"
      "  inside guide\n"
      "  aspiration syringe\n"
      "end\n"
      "tool mc catheter\n"
      "  section 1500 od=0.85 ei=8 gj=6\n"
      "  inner_diameter 0.53\n"
      "  inside asp\n"
      "end\n"
      "tool stent guidewire\n"
      "  section 1700 od=0.4 ei=30 gj=23\n"
      "  inside mc\n"
      "  stent_retriever diameter=4 length=20 embed=180\n"
      "end\n",
      "cases/x.case");
  ASSERT_TRUE(p) << p.error().message;
  ASSERT_EQ(p->tools.size(), 4u);
  EXPECT_EQ(p->tools[0].steered_by_inner, InnerSteering::kNone);
  EXPECT_EQ(p->tools[1].steered_by_inner, InnerSteering::kWhileAdvanced);
  EXPECT_EQ(p->tools[2].steered_by_inner, InnerSteering::kWhileAdvanced);
  EXPECT_EQ(p->tools[3].steered_by_inner, InnerSteering::kNone);
}

TEST(CaseClot, ParsesClotsAndAspiration) {
  const CaseParse p = parse_case(
      "vessel neuro.hclm\n"
      "clot 22 2 13 red=60 fibrin=30\n"
      "clot 25 0 3 open=0.2\n"
      "tool asp catheter\n"
      "  section 1300 od=2.1 ei=30 gj=23\n"
      "  inner_diameter 1.73\n"
      "  aspiration syringe\n"
      "end\n"
      "tool mc catheter\n"
      "  section 1500 od=0.85 ei=8 gj=6\n"
      "  inside asp\n"
      "end\n",
      "cases/x.case");
  ASSERT_TRUE(p) << p.error().message;
  // An aspiration catheter is steered by the tools it carries (tracked over them to the clot), and
  // so is a catheter run in it (by its wire; before, not: convergence.md, "An aspiration stack
  // sub-stepped").
  ASSERT_EQ(p->tools.size(), 2u);
  EXPECT_EQ(p->tools[0].steered_by_inner, InnerSteering::kWhileAdvanced);
  EXPECT_EQ(p->tools[1].steered_by_inner, InnerSteering::kWhileAdvanced);
  ASSERT_EQ(p->clots.size(), 2u);
  EXPECT_EQ(p->clots[0], (CaseClot{22, 2.0, 13.0, {60.0, 30.0}, 0.0, 2}));
  EXPECT_EQ(p->clots[1], (CaseClot{25, 0.0, 3.0, flow::kReferenceComposition, 0.2, 3}));
  ASSERT_EQ(p->aspiration.size(), 1u);
  EXPECT_EQ(p->aspiration[0].tool, "asp");
  EXPECT_EQ(p->aspiration[0].source, flow::VacuumSource::kSyringe60);
}

TEST(CaseClot, BadStatementsNameTheLine) {
  const auto error = [](const std::string& text) {
    const CaseParse p = parse_case("vessel neuro.hclm\n" + text, "cases/x.case");
    return p ? std::string("(parsed)") : p.error().message;
  };
  EXPECT_EQ(error("clot 22 2\n"), "cases/x.case:2: clot: expected SEG FROM_MM LENGTH_MM [red=PCT] [fibrin=PCT] [open=F]");
  EXPECT_EQ(error("clot 22.5 2 13\n"), "cases/x.case:2: clot: segment id must be an integer >= 0");
  EXPECT_EQ(error("clot 22 -1 13\n"), "cases/x.case:2: clot: start must be in [0, 1000] mm along the segment");
  EXPECT_EQ(error("clot 22 2 0\n"), "cases/x.case:2: clot: length must be in (0, 100] mm");
  EXPECT_EQ(error("clot 22 2 13 red=70 fibrin=40\n"), "cases/x.case:2: clot red cells + fibrin/platelets exceed 100 %");
  EXPECT_EQ(error("clot 22 2 13 open=1\n"), "cases/x.case:2: clot: open must be in [0, 1)");
  EXPECT_EQ(error("clot 22 2 13 hard=1\n"), "cases/x.case:2: clot: unknown key 'hard' (known: red fibrin open)");
  EXPECT_EQ(error("clot 22 2 13 red\n"), "cases/x.case:2: clot: expected key=value, got 'red'");
  EXPECT_EQ(error("clot 22 2 13 red=x\n"), "cases/x.case:2: clot red: 'x' is not a finite number");
  std::string many;
  for (int i = 0; i < 17; ++i) many += "clot " + std::to_string(i) + " 0 1\n";
  EXPECT_EQ(error(many), "cases/x.case:18: too many clots (at most 16)");
  EXPECT_EQ(error("tool w guidewire\n section 100 od=0.36 ei=1 gj=1\n aspiration pump\nend\n"),
            "cases/x.case:4: aspiration: only a catheter aspirates");
  EXPECT_EQ(error("tool c catheter\n section 100 od=2 ei=1 gj=1\n inner_diameter 1.7\n aspiration vacuum\nend\n"),
            "cases/x.case:5: aspiration: source must be 'pump' or 'syringe', not 'vacuum'");
  EXPECT_EQ(error("tool c catheter\n section 100 od=2 ei=1 gj=1\n inner_diameter 1.7\n aspiration pump\n aspiration pump\nend\n"),
            "cases/x.case:6: aspiration given twice");
  EXPECT_EQ(error("tool c catheter\n section 100 od=2 ei=1 gj=1\n aspiration pump\nend\n"),
            "cases/x.case:4: aspiration: tool 'c' has no inner_diameter");
}

// `stent_retriever diameter=MM length=MM [embed=S]` on a push wire inside its microcatheter.
TEST(CaseClot, ParsesAStentRetrieverAndNamesTheLineOfABadOne) {
  const std::string tools =
      "tool mc catheter\n section 1500 od=0.8 ei=2 gj=1.6\n inner_diameter 0.53\nend\n"
      "tool sr guidewire\n section 1800 od=0.45 ei=20 gj=15\n";
  const CaseParse p = parse_case("vessel neuro.hclm\n" + tools + " inside mc\n stent_retriever diameter=4 length=20\nend\n", "cases/x.case");
  ASSERT_TRUE(p) << p.error().message;
  EXPECT_EQ(p->tools[1].stent, (StentRetrieverSpec{4.0, 20.0, 180.0}));
  const CaseParse q = parse_case("vessel neuro.hclm\n" + tools + " stent_retriever length=40 diameter=6 embed=240\n inside mc\nend\n", "cases/x.case");
  ASSERT_TRUE(q) << q.error().message;
  EXPECT_EQ(q->tools[1].stent, (StentRetrieverSpec{6.0, 40.0, 240.0}));
  const auto error = [&](const std::string& lines) {
    const CaseParse r = parse_case("vessel neuro.hclm\n" + tools + lines, "cases/x.case");
    return r ? std::string("parsed") : r.error().message;
  };
  // The stent line is line 9 of each text.
  EXPECT_EQ(error(" inside mc\n stent_retriever diameter=2.5 length=20\nend\n"), "cases/x.case:9: stent_retriever: diameter must be in [3, 6] mm");
  EXPECT_EQ(error(" inside mc\n stent_retriever diameter=4 length=45\nend\n"), "cases/x.case:9: stent_retriever: length must be in [20, 40] mm");
  EXPECT_EQ(error(" inside mc\n stent_retriever diameter=4 length=20 embed=0\nend\n"), "cases/x.case:9: stent_retriever: embed must be in (0, 1800] s");
  EXPECT_EQ(error(" inside mc\n stent_retriever diameter=4\nend\n"), "cases/x.case:9: stent_retriever: diameter= and length= are required");
  EXPECT_EQ(error(" inside mc\n stent_retriever diameter=4 length=20 force=1\nend\n"),
            "cases/x.case:9: stent_retriever: unknown key 'force' (known: diameter length embed)");
  EXPECT_EQ(error(" inside mc\n stent_retriever diameter=x length=20\nend\n"), "cases/x.case:9: stent_retriever diameter: 'x' is not a finite number");
  EXPECT_EQ(error(" inside mc\n stent_retriever 4 20\nend\n"), "cases/x.case:9: stent_retriever: expected key=value, got '4'");
  EXPECT_EQ(error(" inside mc\n stent_retriever diameter=4 length=20\n stent_retriever diameter=4 length=20\nend\n"),
            "cases/x.case:10: stent_retriever given twice");
  EXPECT_EQ(error(" section 10 od=0.45 ei=2 gj=1.5\n stent_retriever diameter=4 length=20\nend\n"),
            "cases/x.case:9: stent_retriever: the push wire 'sr' must run inside the catheter that delivers it (inside NAME)");
  EXPECT_EQ(parse_case("tool c catheter\n section 100 od=2 ei=1 gj=1\n stent_retriever diameter=4 length=20\nend\n", "cases/x.case").error().message,
            "cases/x.case:3: stent_retriever: only a push wire (a guidewire tool) carries one");
  EXPECT_EQ(parse_case("tool mc catheter\n section 1500 od=0.8 ei=2 gj=1.6\n inner_diameter 0.53\nend\n"
                       "tool sr guidewire\n section 30 od=0.45 ei=2 gj=1\n inside mc\n stent_retriever diameter=4 length=30\nend\n",
                       "cases/x.case")
                .error()
                .message,
            "cases/x.case:8: stent_retriever: longer than its push wire 'sr'");
}

TEST(CaseClot, ResolvesAgainstTheModelNamingTheLine) {
  const vessel::HclmReadResult m = vessel::load_hclm(source("cases/neuro.hclm"));
  ASSERT_TRUE(m.ok());
  const auto resolve = [&](const std::string& text) {
    const CaseParse p = parse_case("vessel neuro.hclm\n" + text, "cases/x.case");
    EXPECT_TRUE(p) << (p ? "" : p.error().message);
    return resolve_clots(*p, m.model);
  };
  const auto ok = resolve("clot 22 2 13\n");
  ASSERT_TRUE(ok);
  ASSERT_EQ(ok->size(), 1u);
  EXPECT_EQ((*ok)[0].segment, static_cast<std::uint32_t>(*m.model.index_of(22)));
  auto bad = resolve("clot 999 0 5\n");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "cases/x.case:2: clot: no segment 999 in the vessel model");
  bad = resolve("clot 22 10 13\n");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("cases/x.case:2: clot: runs past the end of segment 22"), std::string::npos);
  bad = resolve("clot 22 2 5\nclot 22 6 5\n");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "cases/x.case:3: clot: overlaps another clot in segment 22");
}

// Both bundled thrombectomy cases: the clots occlude their territory in the flow model (eTICI 0)
// and removing them restores it (eTICI 3).
TEST(CaseClot, BundledThrombectomyCasesOccludeAndReperfuse) {
  for (const char* name : {"cases/neuro_thrombectomy_m1.case", "cases/neuro_thrombectomy_ica_t.case"}) {
    const CaseParse c = load_case(source(name));
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_FALSE(c->aspiration.empty()) << name;
    const vessel::HclmReadResult m = vessel::load_hclm(c->vessel_path);
    ASSERT_TRUE(m.ok()) << name;
    const auto clots = resolve_clots(*c, m.model);
    ASSERT_TRUE(clots) << clots.error().message;
    auto net = flow::FlowNetwork::build(m.model, c->flow);
    ASSERT_TRUE(net) << net.error().message;
    const std::vector<flow::Terminal> open = (*net)->terminals();
    ASSERT_TRUE((*net)->occlude(*clots));
    const auto territory = flow::TargetTerritory::find(open, (*net)->terminals());
    ASSERT_TRUE(territory) << name;
    EXPECT_EQ(territory->grade((*net)->terminals()), flow::Etici::k0) << name;
    ASSERT_TRUE((*net)->occlude({}));
    EXPECT_EQ(territory->grade((*net)->terminals()), flow::Etici::k3) << name;
  }
}

}  // namespace
}  // namespace cathbox::tool
