// Small parts of the trainer: case catalog, frame statistics, screen layout.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "app/case_catalog.hpp"
#include "app/frame_stats.hpp"
#include "app/screen_layout.hpp"

namespace cathbox::app {
namespace {

TEST(CaseCatalog, ListsCaseFilesSortedAndPicksTheDefault) {
  const std::filesystem::path dir = std::filesystem::path(CATHBOX_BINARY_DIR) / "case_catalog_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "sub.hclm");
  std::filesystem::create_directories(dir / "lib");
  for (const char* f : {"zeta.hclm", "neuro_l2.hclm", "alpha.hclm", "notes.txt", "neuro_x.case", "lib/kink.case",
                        "lib/kink.hclm"}) {
    std::ofstream(dir / f) << "x";
  }
  const std::vector<std::string> ext = {".hclm", ".case"};
  const base::Result<CaseCatalog> scanned = CaseCatalog::scan(dir.string(), ext);
  ASSERT_TRUE(scanned) << scanned.error().message;
  const CaseCatalog& c = *scanned;
  ASSERT_EQ(c.entries().size(), 5U);
  EXPECT_EQ(c.entries()[0].name, "alpha.hclm");
  EXPECT_EQ(c.entries()[1].name, "lib/kink.case") << "a subfolder's case files, not its vessel files";
  EXPECT_EQ(c.entries()[2].name, "neuro_l2.hclm");
  EXPECT_EQ(c.entries()[3].name, "neuro_x.case");
  EXPECT_EQ(c.entries()[4].name, "zeta.hclm");
  EXPECT_EQ(c.default_index("neuro"), 2);
  EXPECT_EQ(c.default_index("neuro", ".case"), 3);
  EXPECT_EQ(c.default_index("zeta", ".case"), 4);  // no case file: the vessel file
  EXPECT_EQ(c.default_index("absent"), 0);
  EXPECT_EQ(c.index_of_path((dir / "lib" / ".." / "lib" / "kink.case").string()), 1) << "the same file by another path";
}

TEST(CaseCatalog, AMissingFolderIsAnErrorLine) {
  const std::vector<std::string> ext = {".hclm"};
  const base::Result<CaseCatalog> c = CaseCatalog::scan("/no/such/folder", ext);
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().message.find("/no/such/folder"), std::string::npos);
  EXPECT_EQ(CaseCatalog{}.default_index("neuro"), -1) << "the empty list the trainer then shows";
}

TEST(FrameStats, PercentilesAndMeanRate) {
  FrameStats s;
  EXPECT_EQ(s.percentile_us(50), 0.0);
  for (int i = 1; i <= 100; ++i) s.add(i * 100);  // 100 us .. 10 ms
  EXPECT_NEAR(s.percentile_us(50), 5050.0, 1e-9);
  EXPECT_NEAR(s.percentile_us(100), 10000.0, 1e-9);
  EXPECT_NEAR(s.percentile_us(0), 100.0, 1e-9);
  EXPECT_NEAR(s.mean_fps(), 1e6 * 100 / 505000.0, 1e-9);
}

TEST(ScreenLayout, ThreeAreasTileTheWindow) {
  for (const auto& [w, h] : {std::pair{1280, 720}, std::pair{800, 600}, std::pair{300, 900}}) {
    const ScreenLayout l = ScreenLayout::for_window(w, h);
    EXPECT_EQ(l.global.width + l.local.width, w);
    EXPECT_EQ(l.local.width, l.output.width);
    EXPECT_EQ(l.local.height + l.output.height, h);
    EXPECT_EQ(l.global.height, h);
    EXPECT_GE(l.global.width, w * 3 / 5);
  }
}

}  // namespace
}  // namespace cathbox::app
