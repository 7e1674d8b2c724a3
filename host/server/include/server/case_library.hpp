#pragma once
// The centre's case library: uploads checked with the project's own readers (the HCLM reader
// of sim/vessel and the case parser of sim/tool), meshed once at upload to prove the vessel
// builds and to measure it, stored as a zstd bundle, versioned by name.
//
// A refused upload answers 422 with the reader's own line, e.g.
//   neuro.hclm:12: radius must be > 0
//   neuro.case:7: target segment 99 is not a segment of neuro.hclm
//
// Sizes reported per version (the thesis's Table 1 compares model bytes before and after
// compression, 7-15x): raw_bytes (case + HCLM text), wire_bytes (the zstd bundle a download
// sends) and mesh_bytes, the level-2 Catmull-Clark surface the trainer builds from them, counted
// as it sits in memory: 24 bytes per vertex (float32 position and normal) + 12 per triangle
// (three uint32 indices).
#include <string>

#include "server/case_bundle.hpp"
#include "server/result.hpp"
#include "server/store.hpp"
#include "server/upload_limits.hpp"

namespace cathbox::server {

inline constexpr std::size_t kMaxCaseTextBytes = 256 * 1024;
inline constexpr std::size_t kMaxHclmBytes = 8 * 1024 * 1024;

struct CaseCheck {
  CaseBundle bundle;
  std::string title;  // the case file's `name` line
  std::int64_t mesh_vertices = 0;
  std::int64_t mesh_triangles = 0;
  std::int64_t mesh_bytes = 0;
};

// Validates a case and its HCLM (text in memory), checks the vessel against `limits` (413) and
// meshes it at level 2.
[[nodiscard]] Result<CaseCheck> check_case(const CaseBundle& bundle, const UploadLimits& limits = {});

// The vessel surface for a browser (GET /cases/{name}/versions/{v}/mesh): the coarse level the
// trainer's global view draws (subdivision level 1, 4 points a ring), little-endian binary:
//   "CBXMESH1" (8 bytes), u32 vertex count V, u32 triangle count T,
//   f32 positions[3V] (mm), f32 normals[3V] (unit, outward), u32 indices[3T] (counter-clockwise
//   seen from outside).
// A case of 'tube' lines (no HCLM) has no mesh: 404.
inline constexpr int kBrowserMeshLevel = 1;
inline constexpr int kBrowserMeshRingPoints = 4;
[[nodiscard]] Result<std::string> browser_mesh(const CaseBundle& bundle);
// The surface the session's collision tree is built on (GET .../mesh?level=collision), at the
// default mesh options, every field exact: CBXMESH2 (vessel/mesh_wire.hpp), for the
// WebAssembly session, which cannot mesh (no OpenSubdiv). 404 as browser_mesh.
[[nodiscard]] Result<std::string> collision_mesh(const CaseBundle& bundle);

struct CaseUploadOutcome {
  CaseVersion version;
  bool created = false;
};

class CaseLibrary {
 public:
  CaseLibrary(Store& store, int zstd_level = 19) : store_(store), zstd_level_(zstd_level) {}
  [[nodiscard]] Result<CaseUploadOutcome> upload(const std::string& name, const CaseBundle& bundle, std::optional<std::int64_t> uploader_id,
                                                 std::int64_t now_us);

 private:
  Store& store_;
  int zstd_level_;
};

}  // namespace cathbox::server
