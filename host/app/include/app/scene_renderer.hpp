#pragma once
// Draws the scene with few draw calls and cheap shaders (it must hold 60 fps on Mesa's
// software rasteriser): the vessel from a static buffer, semi-transparent (far wall, then near
// wall, over the opaque tools) or as a wireframe; the tools as tubes along their nodes; the
// target as a small sphere. The global view uses a given camera; the local view looks forward
// from the tool tip, inside the lumen, with distance fog.
#include <optional>
#include <span>
#include <string>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "app/gpu_mesh.hpp"
#include "app/mesh_chunks.hpp"
#include "session/scene_snapshot.hpp"
#include "app/shader_program.hpp"
#include "app/tube_mesh.hpp"
#include "app/viewport.hpp"
#include "base/result.hpp"

namespace cathbox::app {

// The renderer draws the session's snapshots.
using session::SceneSnapshot;
using session::ToolView;
using session::ContactView;

struct RenderSettings {
  bool wireframe = false;
  float vessel_alpha = 0.35F;
  // Tools are drawn at least this thick in the global view so a 0.36 mm wire stays visible.
  float min_tool_radius_mm = 0.6F;
};

struct SceneColors {
  static constexpr glm::vec3 kBackground{0.07F, 0.08F, 0.10F};
  static constexpr glm::vec3 kVessel{0.85F, 0.22F, 0.20F};
  static constexpr glm::vec3 kActiveTool{0.25F, 0.95F, 0.40F};
  static constexpr glm::vec3 kOtherTool{0.30F, 0.60F, 0.95F};
  static constexpr glm::vec3 kReleasedCoil{0.85F, 0.80F, 0.70F};  // platinum
  static constexpr glm::vec3 kTarget{1.00F, 0.85F, 0.10F};
  static constexpr glm::vec3 kContact{1.00F, 0.45F, 0.00F};
  static constexpr glm::vec3 kClot{0.35F, 0.03F, 0.05F};  // dark red: a thrombus
  static constexpr glm::vec3 kEmbolus{0.85F, 0.15F, 0.10F};  // bright red: a fragment carried by the flow
};

class SceneRenderer {
 public:
  [[nodiscard]] base::Status<> init();  // or the driver's shader log
  // The vessel surface. `detail` is drawn in the local view (close to the tip, culled by
  // chunks); `overview`, if not empty, in the global view (a coarser level of the same surface,
  // since the global view cannot show sub-pixel triangles and each costs as much to submit).
  struct MeshView {
    std::span<const glm::vec3> positions_mm;
    std::span<const glm::vec3> normals;
    std::span<const std::uint32_t> triangles;
  };
  void set_vessel(const MeshView& detail, const MeshView& overview = {});
  // set_vessel() in two steps, for a vessel that changes while it is shown (a balloon widened
  // the lumen): chunk() does the CPU work (any thread), set_vessel(PreparedVessel) only uploads
  // (the render thread): upload_vessel(). The meshes must outlive the call.
  struct PreparedVessel {
    MeshView detail;
    ChunkedMesh detail_chunks;
    MeshView overview;  // empty: the global view draws the detail mesh
    ChunkedMesh overview_chunks;
  };
  [[nodiscard]] static ChunkedMesh chunk(const MeshView& mesh);
  void upload_vessel(const PreparedVessel& vessel);
  void set_target(std::optional<glm::vec3> target_mm, float radius_mm);

  // Clears the whole framebuffer to the background colour.
  void clear(int framebuffer_width, int framebuffer_height) const;
  // Rebuilds the tool tubes, the released coils' and the wall-contact markers from the snapshot
  // (once per frame, before the views).
  void update_tools(const SceneSnapshot& snapshot, const RenderSettings& settings);
  void render_global(const Viewport& viewport, int framebuffer_height, const glm::mat4& view,
                     const glm::mat4& projection, const RenderSettings& settings);
  void render_local(const Viewport& viewport, int framebuffer_height, const SceneSnapshot& snapshot);

  [[nodiscard]] std::size_t detail_triangles() const { return detail_.gpu.index_count() / 3; }
  [[nodiscard]] std::size_t overview_triangles() const { return overview().gpu.index_count() / 3; }
  // Triangles submitted by the last render_global / render_local call (after culling).
  [[nodiscard]] std::size_t last_global_triangles() const { return last_global_triangles_; }
  [[nodiscard]] std::size_t last_local_triangles() const { return last_local_triangles_; }

 private:
  struct ChunkedGpuMesh {
    GpuMesh gpu;
    std::vector<MeshChunk> chunks;
    void upload(const MeshView& m, const ChunkedMesh& chunked);
    std::size_t draw_visible(const glm::mat4& view_projection, const glm::vec3& eye_mm,
                             float max_distance_mm, std::vector<IndexRange>& scratch) const;
  };
  void draw_tools(bool local) const;
  void update_contacts(const SceneSnapshot& snapshot, float size_mm);
  [[nodiscard]] const ChunkedGpuMesh& overview() const { return has_overview_ ? overview_ : detail_; }

  ShaderProgram shader_;
  ChunkedGpuMesh detail_;
  ChunkedGpuMesh overview_;
  bool has_overview_ = false;
  std::vector<IndexRange> ranges_;
  std::size_t last_global_triangles_ = 0;
  std::size_t last_local_triangles_ = 0;
  GpuMesh target_;
  bool has_target_ = false;
  glm::vec3 target_mm_{0.0F};
  float target_radius_mm_ = 0.0F;
  GpuMesh contacts_;  // a small octahedron at every wall contact
  std::vector<glm::vec3> contact_positions_;
  std::vector<glm::vec3> contact_normals_;
  std::vector<std::uint32_t> contact_triangles_;
  struct ToolDraw {
    GpuMesh global;
    GpuMesh local;
    glm::vec3 color{1.0F};
  };
  // The tools, then the released coils (SceneSnapshot::coils), then the clots (SceneSnapshot::
  // clots: a tube of the clot's radius from its face to its distal end, wherever it is now).
  std::array<ToolDraw, SceneSnapshot::kMaxTools + SceneSnapshot::kMaxCoils + SceneSnapshot::kMaxClots> tools_;
  int tool_count_ = 0;  // tools, coils and clots drawn
  TubeMesh tube_;
  TubeMesh stent_tube_;  // an expanded stent section, appended to tube_
  void build_tool_tube(const ToolView& tv, float radius_mm, float wire_radius_mm);
};

}  // namespace cathbox::app
