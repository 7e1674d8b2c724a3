// The case picker's content (host/app/case_summary.hpp, case_thumbnail.hpp,
// case_picker_model.hpp): the anatomy thumbnail of a generated case draws the vessel where its
// centreline projects (AP: x to the right, z up) and nothing elsewhere, and the picker lists
// every bundled case with its title and description.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "app/case_picker_model.hpp"
#include "app/case_summary.hpp"
#include "app/case_thumbnail.hpp"
#include "vessel/case_library.hpp"
#include "vessel/hclm.hpp"

namespace cathbox::app {
namespace {

constexpr int kSize = 128;

bool is_background(const Image& img, int i, int j) {
  const std::uint8_t* p = img.pixel(i, j);
  return p[0] == ThumbnailColors::kBackground[0] && p[1] == ThumbnailColors::kBackground[1] &&
         p[2] == ThumbnailColors::kBackground[2];
}

// The projection worked out here on its own: the tubes' extent (x and z, with radii) scaled
// uniformly into the image less the renderer's margin (5 %), centred; x right, z up.
struct ExpectedProjection {
  glm::dvec2 centre{0.0};
  double scale = 0.0;
  [[nodiscard]] glm::dvec2 px(const glm::dvec3& p) const {
    return {kSize / 2.0 + (p.x - centre.x) * scale, kSize / 2.0 - (p.z - centre.y) * scale};
  }
};

ExpectedProjection expected_projection(const std::vector<ThumbnailTube>& tubes) {
  double lo_x = std::numeric_limits<double>::infinity();
  double lo_z = lo_x;
  double hi_x = -lo_x;
  double hi_z = -lo_x;
  for (const ThumbnailTube& t : tubes) {
    lo_x = std::min({lo_x, t.a_mm.x - t.radius_a_mm, t.b_mm.x - t.radius_b_mm});
    hi_x = std::max({hi_x, t.a_mm.x + t.radius_a_mm, t.b_mm.x + t.radius_b_mm});
    lo_z = std::min({lo_z, t.a_mm.z - t.radius_a_mm, t.b_mm.z - t.radius_b_mm});
    hi_z = std::max({hi_z, t.a_mm.z + t.radius_a_mm, t.b_mm.z + t.radius_b_mm});
  }
  const double margin = std::max(2.0, kSize * 0.05);
  return {{(lo_x + hi_x) / 2.0, (lo_z + hi_z) / 2.0}, (kSize - 2.0 * margin) / std::max(hi_x - lo_x, hi_z - lo_z)};
}

// Distance in pixels from q to the nearest projected tube's surface outline (negative inside).
double distance_outside_px(const std::vector<ThumbnailTube>& tubes, const ExpectedProjection& proj, const glm::dvec2& q) {
  double best = std::numeric_limits<double>::infinity();
  for (const ThumbnailTube& t : tubes) {
    const glm::dvec2 a = proj.px(t.a_mm);
    const glm::dvec2 d = proj.px(t.b_mm) - a;
    const double len2 = glm::dot(d, d);
    const double u = len2 > 0.0 ? std::clamp(glm::dot(q - a, d) / len2, 0.0, 1.0) : 0.0;
    const double r = std::max(0.5, (t.radius_a_mm + u * (t.radius_b_mm - t.radius_a_mm)) * proj.scale);
    best = std::min(best, glm::length(q - (a + u * d)) - r);
  }
  return best;
}

vessel::LibraryCase library(const char* name) {
  const std::optional<vessel::LibraryCase> c = vessel::library_case(name);
  EXPECT_TRUE(c.has_value()) << name;
  return *c;
}

TEST(CasePicker, ThumbnailDrawsTheVesselWhereItsCentrelineProjects) {
  const vessel::VesselModel model = vessel::library_model(library("aneurysm_basilar"));
  const std::vector<ThumbnailTube> tubes = centreline_tubes(model);
  ASSERT_GT(tubes.size(), 50U);
  const Thumbnail thumb = render_thumbnail(tubes, std::nullopt, kSize);
  ASSERT_EQ(thumb.image.width, kSize);
  ASSERT_EQ(thumb.image.channels, 4);
  const ExpectedProjection proj = expected_projection(tubes);
  ASSERT_NEAR(thumb.projection.px_per_mm(), proj.scale, 1e-9);

  // Every centreline point lands on a drawn pixel.
  for (const vessel::Segment& s : model.segments) {
    for (const vessel::CenterlinePoint& p : s.points) {
      const glm::dvec2 q = proj.px(p.pos_mm);
      EXPECT_FALSE(is_background(thumb.image, static_cast<int>(q.x), static_cast<int>(q.y)))
          << "segment " << s.id << " at (" << q.x << ", " << q.y << ") px";
    }
  }
  // And every drawn pixel lies on a projected tube (its centre within the radius plus the
  // half pixel of the smoothed edge).
  int drawn = 0;
  for (int j = 0; j < kSize; ++j) {
    for (int i = 0; i < kSize; ++i) {
      if (is_background(thumb.image, i, j)) continue;
      ++drawn;
      EXPECT_LE(distance_outside_px(tubes, proj, {i + 0.5, j + 0.5}), 0.5 + 1e-9) << "pixel " << i << ", " << j;
    }
  }
  EXPECT_GT(drawn, kSize * kSize / 50) << "the vessel covers a visible part of the image";
  EXPECT_LT(drawn, kSize * kSize / 2) << "and not the whole of it";
}

TEST(CasePicker, ThumbnailIsNotMirrored) {
  // One tube from the patient's right (x < 0) low to the left high: image left bottom to right top.
  const std::vector<ThumbnailTube> tubes = {{{-20.0, 0.0, 0.0}, {20.0, 0.0, 40.0}, 2.0, 2.0, 1}};
  const Thumbnail thumb = render_thumbnail(tubes, std::nullopt, kSize);
  EXPECT_FALSE(is_background(thumb.image, 16, kSize - 16));
  EXPECT_FALSE(is_background(thumb.image, kSize - 16, 16));
  EXPECT_TRUE(is_background(thumb.image, 16, 16));
  EXPECT_TRUE(is_background(thumb.image, kSize - 16, kSize - 16));
}

TEST(CasePicker, TheTargetIsRinged) {
  const std::vector<ThumbnailTube> tubes = {{{0.0, 0.0, 0.0}, {0.0, 0.0, 50.0}, 1.0, 1.0, 1}};
  const glm::dvec3 target{0.0, 0.0, 25.0};
  const Thumbnail thumb = render_thumbnail(tubes, target, kSize);
  const glm::dvec2 c = thumb.projection.to_px(target);
  const std::uint8_t* ring = thumb.image.pixel(static_cast<int>(c.x + 4.5), static_cast<int>(c.y));
  EXPECT_GT(ring[1], 150) << "the ring's yellow (the vessel's red and the background have green under 100)";
  const Thumbnail without = render_thumbnail(tubes, std::nullopt, kSize);
  EXPECT_TRUE(is_background(without.image, static_cast<int>(c.x + 4.5), static_cast<int>(c.y)));
}

TEST(CasePicker, WithATargetTheViewIsFittedToTheVesselsNearIt) {
  const vessel::VesselModel model = vessel::library_model(library("aneurysm_basilar"));
  const std::vector<ThumbnailTube> tubes = centreline_tubes(model);
  const glm::dvec3 target = model.segments.back().points.front().pos_mm;
  const Thumbnail whole = render_thumbnail(tubes, std::nullopt, kSize);
  const Thumbnail framed = render_thumbnail(tubes, target, kSize);
  EXPECT_GT(framed.projection.px_per_mm(), 2.0 * whole.projection.px_per_mm()) << "the head's vessels, not the whole tree";
  const glm::dvec2 t = framed.projection.to_px(target);
  EXPECT_GT(t.x, 0.0);
  EXPECT_LT(t.x, kSize);
  EXPECT_GT(t.y, 0.0);
  EXPECT_LT(t.y, kSize);
  EXPECT_FALSE(is_background(framed.image, static_cast<int>(t.x), static_cast<int>(t.y)));
}

TEST(CasePicker, NoAnatomyGivesTheBackground) {
  const Thumbnail thumb = render_thumbnail({}, std::nullopt, 32);
  for (int j = 0; j < 32; ++j) {
    for (int i = 0; i < 32; ++i) ASSERT_TRUE(is_background(thumb.image, i, j));
  }
}

TEST(CasePicker, TheDescriptionIsTheFirstCommentBlock) {
  EXPECT_EQ(first_comment_block("cathbox-case 1\n#  One\n# two,\r\n#\n# three\nname x\n# later\n"), "One two, three");
  EXPECT_EQ(first_comment_block("name x\n"), "");
}

TEST(CasePicker, SummarisesAGeneratedCase) {
  const vessel::LibraryCase c = library("aneurysm_acom");
  const vessel::VesselModel model = vessel::library_model(c);
  const std::filesystem::path dir = std::filesystem::path(CATHBOX_BINARY_DIR) / "case_picker_test";
  std::filesystem::create_directories(dir);
  ASSERT_EQ(vessel::save_hclm(model, (dir / (c.name + ".hclm")).string()), "");
  std::ofstream(dir / (c.name + ".case")) << vessel::library_case_text(c, model);
  const CaseSummary s = read_case_summary((dir / (c.name + ".case")).string());
  EXPECT_EQ(s.error, "");
  EXPECT_EQ(s.title, c.title);
  EXPECT_NE(s.description.find("anterior communicating artery"), std::string::npos) << s.description;
  EXPECT_EQ(s.tubes.size(), centreline_tubes(model).size());
  ASSERT_TRUE(s.target_mm.has_value());
  const Thumbnail thumb = render_thumbnail(s.tubes, s.target_mm, kSize);
  const glm::dvec2 t = thumb.projection.to_px(*s.target_mm);
  EXPECT_FALSE(is_background(thumb.image, static_cast<int>(t.x), static_cast<int>(t.y))) << "the target is on the vessel";

  std::ofstream(dir / "broken.case") << "cathbox-case 1\n# A broken case\nvessel missing.hclm\n";
  const CaseSummary broken = read_case_summary((dir / "broken.case").string());
  EXPECT_NE(broken.error.find("missing.hclm"), std::string::npos) << broken.error;
  EXPECT_EQ(broken.description, "A broken case");
  EXPECT_TRUE(broken.tubes.empty());
}

TEST(CasePicker, ListsEveryBundledCaseWithItsDescriptionAndThumbnail) {
  const std::vector<std::string> ext = {".case", ".hclm"};
  const base::Result<CaseCatalog> catalog = CaseCatalog::scan(std::string(CATHBOX_SOURCE_DIR) + "/cases", ext);
  ASSERT_TRUE(catalog) << catalog.error().message;
  CasePickerModel picker;
  ASSERT_TRUE(picker.refresh(*catalog));
  EXPECT_FALSE(picker.refresh(*catalog)) << "the same catalog is not summarised again";
  ASSERT_EQ(picker.entries().size(), catalog->entries().size());
  int library_cases = 0;
  for (const CasePickerEntry& e : picker.entries()) {
    SCOPED_TRACE(e.file.name);
    EXPECT_EQ(e.summary.error, "");
    EXPECT_FALSE(e.summary.description.empty());
    EXPECT_FALSE(e.summary.title.empty());
    int drawn = 0;
    for (int j = 0; j < e.thumbnail.height; ++j) {
      for (int i = 0; i < e.thumbnail.width; ++i) drawn += is_background(e.thumbnail, i, j) ? 0 : 1;
    }
    EXPECT_GT(drawn, 100);
    if (e.file.name.starts_with("library/")) ++library_cases;
  }
  int library_files = 0;
  for (const auto& f : std::filesystem::directory_iterator(std::string(CATHBOX_SOURCE_DIR) + "/cases/library")) {
    library_files += f.path().extension() == ".case" ? 1 : 0;
  }
  EXPECT_GE(library_files, static_cast<int>(vessel::library_case_names().size()));
  EXPECT_EQ(library_cases, library_files) << "the library's cases, not its vessel files";
  const auto acom = std::find_if(picker.entries().begin(), picker.entries().end(),
                                 [](const CasePickerEntry& e) { return e.file.name == "library/aneurysm_acom.case"; });
  ASSERT_NE(acom, picker.entries().end());
  EXPECT_EQ(acom->summary.title, "library: ACom aneurysm");
  EXPECT_TRUE(acom->summary.description.starts_with("Saccular aneurysm of the anterior communicating artery"))
      << "the generator's line repeating the title is left out: " << acom->summary.description;
}

}  // namespace
}  // namespace cathbox::app
