// A case with its own wall (`surface FILE`): the session collides with that surface, the record
// carries its bytes, and the case rebuilt from the record has the same wall whatever the file on
// disk holds by then.
#include <filesystem>
#include <algorithm>
#include <fstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "session/record_format.hpp"
#include "session/record_header.hpp"
#include "session/session.hpp"
#include "session/session_case.hpp"
#include "session/keyboard_hand.hpp"
#include "vessel/case_generator.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_wire.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::session {
namespace {

// The Y bifurcation's HCLM and its level-1 lumen (coarser than a case meshes) in `dir`, and
// y.case naming both with `extra` lines; the lumen's triangle count.
std::size_t write_surface_case(const std::filesystem::path& dir, const std::string& extra) {
  std::filesystem::create_directories(dir);
  const vessel::VesselModel model = vessel::CaseGenerator::y_bifurcation();
  EXPECT_TRUE(vessel::save_hclm(model, (dir / "y.hclm").string()).empty());
  vessel::MeshOptions coarse;
  coarse.subdivision_level = 1;
  const vessel::VesselSurface lumen = vessel::build_vessel_surface(model, coarse);
  EXPECT_TRUE(lumen.ok()) << lumen.error;
  std::ofstream(dir / "lumen.cbxmesh", std::ios::binary) << vessel::encode_mesh_wire(lumen.mesh);
  std::ofstream(dir / "y.case") << "cathbox-case 1\nvessel y.hclm\nsurface lumen.cbxmesh\ntarget 2 1.0\n" << extra;
  return lumen.mesh.triangle_count();
}

TEST(SurfaceCase, TheRecordCarriesTheWallAndRebuildsIt) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("cathbox_surface_case_" + std::to_string(::getpid()));
  const std::size_t triangles = write_surface_case(dir, "");
  const std::string case_path = (dir / "y.case").string();

  SessionCaseLoad loaded = load_session_case(case_path);
  ASSERT_TRUE(loaded) << loaded.error().message;
  const SessionCase& scene = *loaded.value();
  EXPECT_TRUE(scene.surface_given());
  ASSERT_NE(scene.mesh(), nullptr);
  EXPECT_EQ(scene.mesh()->triangle_count(), triangles);
  EXPECT_FALSE(scene.route_mm.empty());  // the graph still gives the route to the target

  RecordHeader h;
  h.case_name = scene.name;
  h.case_file = scene.case_file;
  h.case_text = scene.case_text;
  h.vessel_file = scene.vessel_file;
  h.vessel_text = scene.vessel_text;
  h.surface_file = scene.surface_file;
  h.surface_bytes = scene.surface_bytes;
  h.tools = scene.spec.tools;
  h.entry = scene.entry;
  const std::vector<std::uint8_t> bytes = encode_header(h);
  RecordHeader back;
  std::string what;
  std::size_t offset = 0;
  ASSERT_TRUE(decode_header(bytes, back, what, offset)) << what << " at " << offset;
  EXPECT_EQ(back.surface_file, h.surface_file);
  EXPECT_EQ(back.surface_bytes, h.surface_bytes);

  std::filesystem::remove_all(dir);  // the record alone rebuilds the case
  SessionCaseLoad replayed = session_case_from_record(back);
  ASSERT_TRUE(replayed) << replayed.error().message;
  EXPECT_TRUE(replayed.value()->surface_given());
  EXPECT_EQ(replayed.value()->mesh()->triangle_count(), triangles);

  back.surface_bytes.clear();  // a record naming a surface it does not carry is refused
  const SessionCaseLoad bare = session_case_from_record(back);
  EXPECT_FALSE(bare);
  EXPECT_NE(bare.error().message.find("carries none of its bytes"), std::string::npos);
}

// The case's surface with a compliant wall (`wall intracranial`, radius from the graph) and a
// pulse (`flow pulsatile 60 1`): the simulator collides with the surface moved by the pulse. The
// flow scales by 1 + (PI / 2) sin(2 pi t), so the transmural pressure over the mean swings by
// PI / 2 of the inlet's pressure above venous (about 88 mmHg: +-44 mmHg, a pulse pressure as
// the carotid's), and every segment's wall by its Laplace P R^2 / (E h).
TEST(SurfaceCase, ACompliantSurfaceDistendsWithThePulse) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("cathbox_surface_pulse_" + std::to_string(::getpid()));
  write_surface_case(dir, "wall intracranial\nflow pulsatile 60 1\n");
  const std::string case_path = (dir / "y.case").string();
  SessionCaseLoad loaded = load_session_case(case_path);
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(loaded) << loaded.error().message;
  KeyboardInput keys;
  Session s(std::move(loaded.value()), std::make_unique<KeyboardHand>(keys, 1e-3));
  const tool::CaseWallField* field = s.wall_field();
  ASSERT_NE(field, nullptr);
  EXPECT_EQ(&s.simulator().wall(), &field->wall());  // the tools meet the moved surface
  double low = 0.0, high = 0.0;
  std::uint64_t revision = field->wall().revision();
  int moved = 0;
  for (int i = 0; i < 1000; ++i) {  // one heart beat
    s.step_virtual(1);
    low = std::min(low, field->pressure_kPa());
    high = std::max(high, field->pressure_kPa());
    if (field->wall().revision() != revision) ++moved;
    revision = field->wall().revision();
  }
  const double swing_mmHg = 44.0;  // PI / 2 of ~88 mmHg
  EXPECT_NEAR(high / 0.133322, swing_mmHg, 0.1 * swing_mmHg);
  EXPECT_NEAR(low / 0.133322, -swing_mmHg, 0.1 * swing_mmHg);
  EXPECT_GT(moved, 990);
  // The parent's wall (R from the graph, intracranial material) moves by P R^2 / (E h).
  const double r = field->distension().radius_mm(0);
  EXPECT_NEAR(field->distension().compliance_mm_per_kPa(0), r * r / (1540.0 * 0.15 * r), 1e-12);
  std::printf("pulse on the surface: %.1f .. %.1f mmHg; parent R %.2f mm moves %.1f .. %.1f um\n", low / 0.133322,
              high / 0.133322, r, 1e3 * low * field->distension().compliance_mm_per_kPa(0),
              1e3 * high * field->distension().compliance_mm_per_kPa(0));
}

}  // namespace
}  // namespace cathbox::session
