#include "app/scene_renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

#include "app/gl.hpp"
#include "app/orbit_camera.hpp"
#include "app/stent_view.hpp"

namespace cathbox::app {
namespace {

// Headlight shading (light at the eye), two-sided so the inside of the vessel is lit too,
// evaluated per vertex: the fragment shader only blends three numbers, which matters on a
// software rasteriser (the meshes are fine enough that Gouraud shading looks smooth).
constexpr const char* kVertexShader = R"(#version 330 core
in vec3 in_position;
in vec3 in_normal;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform vec4 u_fog;  // rgb, and the distance in mm at which the fog is complete (0: none)
out vec2 v_light;    // diffuse factor, specular term
out float v_fog;
void main() {
  vec4 p = u_view * vec4(in_position, 1.0);
  vec3 n = normalize(mat3(u_view) * in_normal);
  float d = abs(dot(n, normalize(-p.xyz)));
  v_light = vec2(0.35 + 0.65 * d, 0.25 * pow(d, 24.0));
  v_fog = u_fog.a > 0.0 ? clamp(length(p.xyz) / u_fog.a, 0.0, 1.0) : 0.0;
  gl_Position = u_proj * p;
}
)";

constexpr const char* kFragmentShader = R"(#version 330 core
in vec2 v_light;
in float v_fog;
uniform vec4 u_color;
uniform vec4 u_fog;
out vec4 frag;
void main() {
  frag = vec4(mix(u_color.rgb * v_light.x + vec3(v_light.y), u_fog.rgb, v_fog), u_color.a);
}
)";

constexpr float kChunkCell_mm = 12.0F;
constexpr float kLocalFog_mm = 40.0F;  // the local view fades to the fog colour at this distance

void set_viewport(const Viewport& vp, int framebuffer_height) {
  glViewport(vp.x, framebuffer_height - vp.y - vp.height, vp.width, vp.height);
  glScissor(vp.x, framebuffer_height - vp.y - vp.height, vp.width, vp.height);
}

void make_sphere(float radius, const glm::vec3& centre, std::vector<glm::vec3>& p,
                 std::vector<glm::vec3>& n, std::vector<std::uint32_t>& t) {
  constexpr int kRings = 8;
  constexpr int kSlices = 12;
  for (int i = 0; i <= kRings; ++i) {
    const float phi = 3.1415927F * static_cast<float>(i) / kRings;
    for (int j = 0; j < kSlices; ++j) {
      const float th = 6.2831853F * static_cast<float>(j) / kSlices;
      const glm::vec3 d{std::sin(phi) * std::cos(th), std::sin(phi) * std::sin(th), std::cos(phi)};
      p.push_back(centre + radius * d);
      n.push_back(d);
    }
  }
  for (std::uint32_t i = 0; i < kRings; ++i) {
    for (std::uint32_t j = 0; j < kSlices; ++j) {
      const std::uint32_t a = i * kSlices + j;
      const std::uint32_t b = i * kSlices + (j + 1) % kSlices;
      t.insert(t.end(), {a, a + kSlices, b + kSlices, a, b + kSlices, b});
    }
  }
}

}  // namespace

base::Status<> SceneRenderer::init() {
  if (base::Status<> built = shader_.build(kVertexShader, kFragmentShader); !built) return built;
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_SCISSOR_TEST);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  return base::Ok{};
}

ChunkedMesh SceneRenderer::chunk(const MeshView& mesh) {
  return ChunkedMesh::build(mesh.positions_mm, mesh.triangles, kChunkCell_mm);
}

void SceneRenderer::ChunkedGpuMesh::upload(const MeshView& m, const ChunkedMesh& chunked) {
  gpu.upload(m.positions_mm, m.normals, chunked.triangles, false);
  chunks = chunked.chunks;
}

std::size_t SceneRenderer::ChunkedGpuMesh::draw_visible(const glm::mat4& view_projection,
                                                        const glm::vec3& eye_mm, float max_distance_mm,
                                                        std::vector<IndexRange>& scratch) const {
  visible_ranges(chunks, view_projection, eye_mm, max_distance_mm, scratch);
  gpu.draw_ranges(scratch);
  std::size_t n = 0;
  for (const IndexRange& r : scratch) n += r.index_count / 3;
  return n;
}

void SceneRenderer::set_vessel(const MeshView& detail, const MeshView& overview) {
  upload_vessel(PreparedVessel{detail, chunk(detail), overview, overview.triangles.empty() ? ChunkedMesh{} : chunk(overview)});
}

void SceneRenderer::upload_vessel(const PreparedVessel& vessel) {
  detail_.upload(vessel.detail, vessel.detail_chunks);
  has_overview_ = !vessel.overview.triangles.empty();
  if (has_overview_) overview_.upload(vessel.overview, vessel.overview_chunks);
}

void SceneRenderer::set_target(std::optional<glm::vec3> target_mm, float radius_mm) {
  has_target_ = target_mm.has_value();
  if (!has_target_) return;
  target_mm_ = *target_mm;
  target_radius_mm_ = radius_mm;
  std::vector<glm::vec3> p;
  std::vector<glm::vec3> n;
  std::vector<std::uint32_t> t;
  make_sphere(radius_mm, *target_mm, p, n, t);
  target_.upload(p, n, t, false);
}

void SceneRenderer::clear(int framebuffer_width, int framebuffer_height) const {
  glViewport(0, 0, framebuffer_width, framebuffer_height);
  glScissor(0, 0, framebuffer_width, framebuffer_height);
  glDepthMask(GL_TRUE);
  glClearColor(SceneColors::kBackground.r, SceneColors::kBackground.g, SceneColors::kBackground.b,
               1.0F);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void SceneRenderer::update_tools(const SceneSnapshot& snapshot, const RenderSettings& settings) {
  const int tools = std::min(snapshot.tool_count, SceneSnapshot::kMaxTools);
  tool_count_ = tools + std::min(snapshot.coil_count, SceneSnapshot::kMaxCoils);
  for (int i = 0; i < tool_count_; ++i) {
    const bool coil = i >= tools;
    const ToolView& tv = coil ? snapshot.coils[static_cast<std::size_t>(i - tools)] : snapshot.tools[static_cast<std::size_t>(i)];
    ToolDraw& td = tools_[static_cast<std::size_t>(i)];
    td.color = coil ? SceneColors::kReleasedCoil : tv.active ? SceneColors::kActiveTool : SceneColors::kOtherTool;
    build_tool_tube(tv, std::max(tv.radius_mm, settings.min_tool_radius_mm), std::max(tv.wire_radius_mm, settings.min_tool_radius_mm));
    td.global.upload(tube_.positions_mm, tube_.normals, tube_.triangles, true);
    build_tool_tube(tv, tv.radius_mm, tv.wire_radius_mm);
    td.local.upload(tube_.positions_mm, tube_.normals, tube_.triangles, true);
  }
  const int clots = std::min(snapshot.clot_count, SceneSnapshot::kMaxClots);
  for (int k = 0; k < clots; ++k) {
    const session::ClotView& c = snapshot.clots[static_cast<std::size_t>(k)];
    ToolDraw& td = tools_[static_cast<std::size_t>(tool_count_++)];
    td.color = c.state == session::ClotState::kInTransit ? SceneColors::kEmbolus : SceneColors::kClot;
    tube_.build(c.axis_mm, {}, c.radius_mm, 12);
    td.global.upload(tube_.positions_mm, tube_.normals, tube_.triangles, true);
    td.local.upload(tube_.positions_mm, tube_.normals, tube_.triangles, true);
  }
  update_contacts(snapshot, settings.min_tool_radius_mm);
}

// A tool's tube at radius_mm; an expanded stent retriever's push wire at wire_radius_mm up to
// its stent section, the section at radius_mm (one mesh: the two tubes share the split node).
void SceneRenderer::build_tool_tube(const ToolView& tv, float radius_mm, float wire_radius_mm) {
  const std::size_t split = expanded_stent_first_node(tv, tv.nodes_mm);
  if (split == 0) {
    tube_.build(tv.nodes_mm, tv.frames, radius_mm);
    return;
  }
  const std::span<const glm::vec3> nodes(tv.nodes_mm);
  const std::span<const glm::vec3> frames(tv.frames);
  const bool framed = frames.size() == nodes.size();
  stent_tube_.build(nodes.subspan(split), framed ? frames.subspan(split) : frames.first(0), radius_mm);
  tube_.build(nodes.first(split + 1), framed ? frames.first(split + 1) : frames.first(0), wire_radius_mm);
  const auto base = static_cast<std::uint32_t>(tube_.positions_mm.size());
  tube_.positions_mm.insert(tube_.positions_mm.end(), stent_tube_.positions_mm.begin(), stent_tube_.positions_mm.end());
  tube_.normals.insert(tube_.normals.end(), stent_tube_.normals.begin(), stent_tube_.normals.end());
  for (const std::uint32_t i : stent_tube_.triangles) tube_.triangles.push_back(base + i);
}

void SceneRenderer::update_contacts(const SceneSnapshot& snapshot, float size_mm) {
  static constexpr glm::vec3 kAxes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  // Faces of the octahedron as (x, y, z) axis picks, counter-clockwise from outside.
  static constexpr std::uint32_t kFaces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  contact_positions_.clear();
  contact_normals_.clear();
  contact_triangles_.clear();
  for (const ContactView& c : snapshot.contacts) {
    const auto base = static_cast<std::uint32_t>(contact_positions_.size());
    for (const glm::vec3& a : kAxes) {
      contact_positions_.push_back(c.point_mm + size_mm * a);
      contact_normals_.push_back(a);
    }
    for (const auto& f : kFaces) contact_triangles_.insert(contact_triangles_.end(), {base + f[0], base + f[1], base + f[2]});
  }
  contacts_.upload(contact_positions_, contact_normals_, contact_triangles_, true);
}

void SceneRenderer::draw_tools(bool local) const {
  for (int i = 0; i < tool_count_; ++i) {
    const ToolDraw& td = tools_[static_cast<std::size_t>(i)];
    shader_.set("u_color", glm::vec4(td.color, 1.0F));
    (local ? td.local : td.global).draw();
  }
}

void SceneRenderer::render_global(const Viewport& viewport, int framebuffer_height,
                                  const glm::mat4& view, const glm::mat4& projection,
                                  const RenderSettings& settings) {
  set_viewport(viewport, framebuffer_height);
  shader_.use();
  shader_.set("u_view", view);
  shader_.set("u_proj", projection);
  shader_.set("u_fog", glm::vec4(0.0F));

  // Opaque first: tools and target write depth.
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  draw_tools(false);
  if (has_target_) {
    shader_.set("u_color", glm::vec4(SceneColors::kTarget, 1.0F));
    target_.draw();
  }
  shader_.set("u_color", glm::vec4(SceneColors::kContact, 1.0F));
  contacts_.draw();

  // The vessel over them, without writing depth so the tools show through.
  glEnable(GL_BLEND);
  glDepthMask(GL_FALSE);
  if (settings.wireframe) {
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    shader_.set("u_color", glm::vec4(SceneColors::kVessel, std::min(1.0F, 2.0F * settings.vessel_alpha)));
    last_global_triangles_ = overview().draw_visible(projection * view, glm::vec3(0.0F), 0.0F, ranges_);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  } else {
    // The near wall only, translucent over the opaque tools: one pass, no sorting. (The far
    // wall too would cost a quarter of the frame on a software rasteriser, where setting up
    // and binning triangles dominates, for little more depth cue.)
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    shader_.set("u_color", glm::vec4(SceneColors::kVessel, settings.vessel_alpha));
    last_global_triangles_ = overview().draw_visible(projection * view, glm::vec3(0.0F), 0.0F, ranges_);
    glDisable(GL_CULL_FACE);
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}

void SceneRenderer::render_local(const Viewport& viewport, int framebuffer_height,
                                 const SceneSnapshot& snapshot) {
  set_viewport(viewport, framebuffer_height);
  constexpr glm::vec3 kFog{0.10F, 0.02F, 0.02F};
  glClearColor(kFog.r, kFog.g, kFog.b, 1.0F);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  shader_.use();
  const glm::mat4 view = EndoCamera::view(snapshot.tip_mm, snapshot.tip_direction, snapshot.tip_up);
  const glm::mat4 projection = EndoCamera::projection(viewport.aspect());
  shader_.set("u_view", view);
  shader_.set("u_proj", projection);
  shader_.set("u_fog", glm::vec4(kFog, kLocalFog_mm));
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  // Inside the lumen every wall in sight faces away (the normals point out of the vessel).
  glEnable(GL_CULL_FACE);
  glCullFace(GL_FRONT);
  shader_.set("u_color", glm::vec4(0.95F, 0.55F, 0.50F, 1.0F));
  const glm::vec3 eye = glm::vec3(glm::inverse(view)[3]);
  last_local_triangles_ = detail_.draw_visible(projection * view, eye, kLocalFog_mm, ranges_);
  glDisable(GL_CULL_FACE);
  draw_tools(true);
  // The target marker, unless the eye is inside it (the tip has arrived).
  if (has_target_ && glm::distance(eye, target_mm_) > target_radius_mm_ + 0.1F) {
    shader_.set("u_color", glm::vec4(SceneColors::kTarget, 1.0F));
    target_.draw();
  }
}

}  // namespace cathbox::app
