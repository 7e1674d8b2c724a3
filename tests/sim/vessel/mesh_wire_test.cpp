// The CBXMESH2 codec (vessel/mesh_wire.hpp): a bundled vessel's surface survives encode ->
// decode exactly (every float bit, every region), which is what lets the WebAssembly session
// run on a surface meshed elsewhere; every malformed input is one error naming its byte.
#include <gtest/gtest.h>

#include <cstdint>
#include <span>
#include <string>

#include "vessel/hclm.hpp"
#include "vessel/mesh_wire.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::vessel {
namespace {

std::span<const std::uint8_t> bytes_of(const std::string& s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

SurfaceMesh y_bifurcation() {
  const VesselSurface s = load_vessel_surface(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.hclm");
  EXPECT_TRUE(s.ok()) << s.error;
  return s.mesh;
}

TEST(MeshWire, RoundTripIsExact) {
  const SurfaceMesh mesh = y_bifurcation();
  ASSERT_GT(mesh.triangle_count(), 1000U);
  const std::string wire = encode_mesh_wire(mesh);
  EXPECT_EQ(wire.substr(0, 8), "CBXMESH2");
  EXPECT_EQ(wire.size(), 16 + 24 * mesh.vertex_count() + 17 * mesh.triangle_count());
  const base::Result<SurfaceMesh> back = decode_mesh_wire(bytes_of(wire));
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back.value().positions_mm, mesh.positions_mm);
  EXPECT_EQ(back.value().normals, mesh.normals);
  EXPECT_EQ(back.value().triangles, mesh.triangles);
  EXPECT_EQ(back.value().triangle_regions, mesh.triangle_regions);
}

TEST(MeshWire, MeshingElsewhereGivesTheSameSurfaceAndCentreline) {
  const HclmReadResult read = load_hclm(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.hclm");
  ASSERT_TRUE(read.ok());
  const VesselSurface meshed = build_vessel_surface(read.model);
  const VesselSurface given = build_vessel_surface(read.model, meshed.mesh);
  ASSERT_TRUE(given.ok()) << given.error;
  EXPECT_EQ(given.smoothed, meshed.smoothed);
  EXPECT_EQ(given.euler_characteristic, meshed.euler_characteristic);
  EXPECT_EQ(given.mesh.positions_mm, meshed.mesh.positions_mm);
  EXPECT_FALSE(build_vessel_surface(read.model, SurfaceMesh{}).ok());
}

TEST(MeshWire, RefusesMalformedInputNamingTheByte) {
  const std::string wire = encode_mesh_wire(y_bifurcation());
  const auto error_of = [](const std::string& w) {
    const base::Result<SurfaceMesh> r = decode_mesh_wire(bytes_of(w));
    return r ? std::string("accepted") : r.error().message;
  };
  EXPECT_EQ(error_of(wire.substr(0, 10)), "byte 10: truncated header (10 bytes)");
  EXPECT_EQ(error_of("CBXMESH1" + wire.substr(8)), "byte 0: not a CBXMESH2 mesh");
  EXPECT_EQ(error_of(wire.substr(0, 1000)).rfind("byte 1000: truncated: ", 0), 0U);
  EXPECT_EQ(error_of(wire + "x"), "byte " + std::to_string(wire.size()) + ": 1 bytes after the mesh");
  std::string huge = wire;
  huge[11] = 0x7f;  // vertex count's high byte
  EXPECT_EQ(error_of(huge).rfind("byte 8: ", 0), 0U);
  EXPECT_NE(error_of(huge).find("vertices, over the limit"), std::string::npos);
  const SurfaceMesh mesh = y_bifurcation();
  const std::size_t first_index = 16 + 24 * mesh.vertex_count();
  std::string bad_index = wire;
  bad_index[first_index + 3] = 0x7f;
  EXPECT_EQ(error_of(bad_index).rfind("byte " + std::to_string(first_index) + ": vertex index ", 0), 0U);
  std::string bad_region = wire;
  bad_region[first_index + 12 * mesh.triangle_count()] = 9;
  EXPECT_EQ(error_of(bad_region), "byte " + std::to_string(first_index + 12 * mesh.triangle_count()) + ": region kind 9");
}

}  // namespace
}  // namespace cathbox::vessel
