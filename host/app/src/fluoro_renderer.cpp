#include "app/fluoro_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "app/fluoro_shaders.hpp"
#include "app/gl.hpp"
#include "fluoro_render_parts.hpp"

// The renderer's GL resources, the phantom's projection and the scene targets each pulse's
// iodine and tools are accumulated into (the monitor image: fluoro_monitor.cpp; the tools'
// tubes: fluoro_tools.cpp; the targets' cells: fluoro_cells.cpp).
namespace cathbox::app {
namespace {

using namespace fluoro_parts;  // the texture units, the hasher

std::uint64_t scene_key(const FluoroScene& s, const flow::CArmPose& pose, double keV, int w, int h, std::uint64_t gen) {
  Hasher k;
  hash_pose(k, pose);
  k.add(keV);
  k.add(w);
  k.add(h);
  k.add(gen);
  k.add_bytes(s.cell_iodine_mgI_ml.data(), s.cell_iodine_mgI_ml.size() * sizeof(float));
  for (const FluoroTool& t : s.tools) {
    k.add_bytes(t.nodes_mm.data(), t.nodes_mm.size() * sizeof(glm::vec3));
    k.add(t.radius_mm);
    k.add(t.material);
    for (const FluoroMarker& m : t.markers) {
      k.add(m.from_tip_mm);
      k.add(m.length_mm);
      k.add(m.material);
    }
    k.add(t.nodes_mm.size());
  }
  return k.digest();
}

}  // namespace

FluoroRenderer::~FluoroRenderer() {
  if (monitor_.fbo != 0) glDeleteFramebuffers(1, &monitor_.fbo);
  if (scaled_.fbo != 0) glDeleteFramebuffers(1, &scaled_.fbo);
  if (compose_fbo_ != 0) glDeleteFramebuffers(1, &compose_fbo_);
  for (Target& t : targets_) {
    if (t.fbo != 0) glDeleteFramebuffers(1, &t.fbo);
    if (t.texture != 0) glDeleteTextures(1, &t.texture);
  }
  const unsigned textures[] = {phantom_texture_, cells_texture_, monitor_.texture, scaled_.texture};
  for (const unsigned t : textures) {
    if (t != 0) glDeleteTextures(1, &t);
  }
  const unsigned buffers[] = {vessel_vbo_, vessel_ebo_, cells_buffer_, tools_vbo_, tools_ebo_};
  for (const unsigned b : buffers) {
    if (b != 0) glDeleteBuffers(1, &b);
  }
  if (linear_sampler_ != 0) glDeleteSamplers(1, &linear_sampler_);
  const unsigned arrays[] = {empty_vao_, vessel_vao_, tools_vao_};
  for (const unsigned a : arrays) {
    if (a != 0) glDeleteVertexArrays(1, &a);
  }
}

base::Status<> FluoroRenderer::init(bool framebuffer_fetch) {
  framebuffer_fetch_wanted_ = framebuffer_fetch;
  // The shared texts (app/fluoro_shaders.hpp) in the desktop dialect, `defines` after the version.
  const auto desktop = [](const char* body, const std::string& defines = {}) {
    return fluoro_glsl::kDesktopVersion + defines + body;
  };
  if (base::Status<> built = scene_shader_.build(desktop(fluoro_glsl::kSceneVertex).c_str(),
                                                 desktop(fluoro_glsl::kSceneFragment).c_str());
      !built) {
    return built;
  }
  GLint extensions = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &extensions);
  fbfetch_ = false;
  for (GLint i = 0; i < extensions && framebuffer_fetch_wanted_; ++i) {
    const auto* name = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
    if (name != nullptr && std::strcmp(name, "GL_EXT_shader_framebuffer_fetch") == 0) fbfetch_ = true;
  }
  for (std::size_t i = 0; i < composite_shaders_.size(); ++i) {
    const std::string source = desktop(
        fluoro_glsl::kCompositeFragment,
        std::string(fbfetch_ ? "#extension GL_EXT_shader_framebuffer_fetch : require\n#define FBFETCH 1\n" : "#define FBFETCH 0\n") +
            "#define MODE " + std::to_string(i % 3) + "\n#define SCENE " + std::to_string(i < 3 ? 1 : 0) + "\n");
    if (base::Status<> built = composite_shaders_[i].build(desktop(fluoro_glsl::kFullViewportVertex).c_str(), source.c_str());
        !built) {
      return built;
    }
  }
  if (base::Status<> built = scale_shader_.build(desktop(fluoro_glsl::kFullViewportVertex).c_str(),
                                                 desktop(fluoro_glsl::kScaleFragment).c_str());
      !built) {
    return built;
  }
  glGenVertexArrays(1, &empty_vao_);
  glGenSamplers(1, &linear_sampler_);
  glSamplerParameteri(linear_sampler_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glSamplerParameteri(linear_sampler_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glSamplerParameteri(linear_sampler_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(linear_sampler_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

  glGenTextures(1, &phantom_texture_);
  glBindTexture(GL_TEXTURE_2D, phantom_texture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);

  // The cells' iodine, one float each, read by the vessel's vertices.
  glGenBuffers(1, &cells_buffer_);
  glBindBuffer(GL_TEXTURE_BUFFER, cells_buffer_);
  const float zero = 0.0F;
  glBufferData(GL_TEXTURE_BUFFER, sizeof zero, &zero, GL_STREAM_DRAW);
  glGenTextures(1, &cells_texture_);
  glBindTexture(GL_TEXTURE_BUFFER, cells_texture_);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_R32F, cells_buffer_);
  glBindTexture(GL_TEXTURE_BUFFER, 0);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);

  for (unsigned* vao : {&vessel_vao_, &tools_vao_}) {
    unsigned& vbo = vao == &vessel_vao_ ? vessel_vbo_ : tools_vbo_;
    unsigned& ebo = vao == &vessel_vao_ ? vessel_ebo_ : tools_ebo_;
    glGenVertexArrays(1, vao);
    glGenBuffers(1, &vbo);
    glGenBuffers(1, &ebo);
    glBindVertexArray(*vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
    glBindVertexArray(0);
  }
  return base::Ok{};
}

void FluoroRenderer::set_phantom(flow::HeadPhantom phantom) {
  phantom_ = std::move(phantom);
  ++generation_;
  projections_.forget();
}

void FluoroRenderer::set_vessel(const FluoroVessel& vessel) { upload_vessel(prepare_vessel(vessel)); }

void FluoroRenderer::upload_vessel(VesselBuffers buffers) {
  const std::vector<float>& v = buffers.vertices;
  const std::vector<std::uint32_t>& sorted = buffers.indices;
  glBindVertexArray(vessel_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vessel_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(v.size() * sizeof(float)), v.data(), GL_STATIC_DRAW);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(sorted.size() * sizeof(std::uint32_t)), sorted.data(),
               GL_STATIC_DRAW);
  glBindVertexArray(0);
  vessel_indices_ = sorted.size();
  buckets_ = std::move(buffers.buckets);
  cell_count_ = buffers.cell_count;
  glBindBuffer(GL_TEXTURE_BUFFER, cells_buffer_);
  glBufferData(GL_TEXTURE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(cell_count_, 1) * sizeof(float)), nullptr,
               GL_STREAM_DRAW);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);
  ++generation_;
}

std::uint64_t FluoroRenderer::phantom_key(const flow::CArm& carm, const Matrix& size) const {
  Hasher k;
  hash_pose(k, carm.pose());
  k.add(size.width);
  k.add(size.height);
  k.add(generation_);
  return k.digest();
}

bool FluoroRenderer::project_phantom(const flow::CArm& carm, const Matrix& size, const Matrix& other, double l_ref) {
  const int width = size.width;
  const int height = size.height;
  const PhantomProjections::Request request{phantom_key(carm, size), {width, height}, phantom_key(carm, other), {other.width, other.height}};
  bool projected = false;
  switch (projections_.use(phantom_, carm, request, monitor_.valid, projected)) {
    case PhantomProjections::Outcome::kWaiting: work_.waiting_for_phantom = true; return false;
    case PhantomProjections::Outcome::kChanged: phantom_l_ref_ = -1.0; break;
    case PhantomProjections::Outcome::kSame: break;
  }
  work_.phantom_projected = projected;
  const std::vector<float>& path = projections_.path();
  if (l_ref == phantom_l_ref_) return true;
  // Each pixel: the phantom's L and the noise amplitude there, sqrt(T_ref / T) = exp((L - L_ref) / 2).
  // Stored bottom row first, as the GL targets it is drawn with.
  phantom_rg_.resize(2 * path.size());
  for (std::size_t i = 0; i < path.size(); ++i) {
    const std::size_t row = i / static_cast<std::size_t>(width);
    const std::size_t o = 2 * ((static_cast<std::size_t>(height) - 1 - row) * static_cast<std::size_t>(width) + i % static_cast<std::size_t>(width));
    phantom_rg_[o] = path[i];
    phantom_rg_[o + 1] = static_cast<float>(std::exp(0.5 * (path[i] - l_ref)));
  }
  phantom_l_ref_ = l_ref;
  glBindTexture(GL_TEXTURE_2D, phantom_texture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RG32F, width, height, 0, GL_RG, GL_FLOAT, phantom_rg_.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  return true;
}

void FluoroRenderer::ensure_target(Target& t, int width, int height, unsigned internal_format, unsigned type) {
  if (t.texture != 0 && t.width == width && t.height == height) return;
  if (t.texture == 0) {
    glGenTextures(1, &t.texture);
    glGenFramebuffers(1, &t.fbo);
  }
  glBindTexture(GL_TEXTURE_2D, t.texture);
  glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal_format), width, height, 0, GL_RGBA, type, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glBindTexture(GL_TEXTURE_2D, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, t.fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t.texture, 0);
  t.width = width;
  t.height = height;
  t.valid = false;
  t.dirty.reset(width, height, true);  // undefined contents
  t.drawn.reset(width, height, false);
}

void FluoroRenderer::accumulate(Target& t, const FluoroScene& scene, const flow::CArm& carm, double keV, int width,
                                int height) {
  const std::uint64_t key = scene_key(scene, carm.pose(), keV, width, height, generation_);
  if (t.valid && t.key == key) return;
  ensure_target(t, width, height, GL_RGBA32F, GL_FLOAT);
  const bool contrast = vessel_indices_ > 0 && scene.cell_iodine_mgI_ml.size() == cell_count_ &&
                        std::any_of(scene.cell_iodine_mgI_ml.begin(), scene.cell_iodine_mgI_ml.end(), [](float c) { return c > 0.0F; });
  // The runs of vessel buckets that read a cell with iodine, and the screen box of all that is drawn.
  lit_runs_.clear();
  drawn_.reset(width, height, false);
  if (contrast) {
    nonzero_before_.assign(cell_count_ + 1, 0);
    for (std::size_t i = 0; i < cell_count_; ++i) {
      nonzero_before_[i + 1] = nonzero_before_[i] + (scene.cell_iodine_mgI_ml[i] > 0.0F ? 1U : 0U);
    }
    for (const Bucket& b : buckets_) {
      if (b.hi >= cell_count_ || nonzero_before_[b.hi + 1] == nonzero_before_[b.lo]) continue;
      ScreenBox box(carm, width, height);
      box.add_box(b.box_min, b.box_max);
      drawn_.mark(box.rect());
      if (!lit_runs_.empty() && lit_runs_.back().first + lit_runs_.back().second == b.first_index) {
        lit_runs_.back().second += b.index_count;
      } else {
        lit_runs_.emplace_back(b.first_index, b.index_count);
      }
    }
  }
  drawn_.mark(build_tools(scene, carm, keV, width, height));
  const Rect drawn = drawn_.bounds();
  // Clear what may be non-zero where this scene draws nothing, and where it draws.
  glBindFramebuffer(GL_FRAMEBUFFER, t.fbo);
  glViewport(0, 0, width, height);
  glEnable(GL_SCISSOR_TEST);
  t.dirty.unite(drawn_);
  glClearColor(0.0F, 0.0F, 0.0F, 0.0F);
  for (const Rect& clear : t.dirty.runs(true)) {
    glScissor(clear.x0, clear.y0, clear.x1 - clear.x0, clear.y1 - clear.y0);
    glClear(GL_COLOR_BUFFER_BIT);
  }
  t.drawn = drawn_;
  t.dirty = drawn_;
  if (!drawn.empty()) {
    glScissor(drawn.x0, drawn.y0, drawn.x1 - drawn.x0, drawn.y1 - drawn.y0);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE);
    scene_shader_.use();
    const double sod = carm.depth_mm(carm.isocenter_mm());
    const glm::mat4 vp = carm.projection_matrix(width, height, 0.25 * sod, carm.pose().sid_mm) * carm.view_matrix();
    scene_shader_.set("u_view_proj", vp);
    scene_shader_.set("u_source", glm::vec4(glm::vec3(carm.source_mm()), static_cast<float>(sod)));
    scene_shader_.set("u_iodine_mu", static_cast<float>(flow::iodine_per_mm_per_mgI_ml(keV)));
    scene_shader_.set_int("u_cells", kCellsUnit);
    if (!lit_runs_.empty()) {
      glBindBuffer(GL_TEXTURE_BUFFER, cells_buffer_);
      glBufferSubData(GL_TEXTURE_BUFFER, 0, static_cast<GLsizeiptr>(cell_count_ * sizeof(float)), scene.cell_iodine_mgI_ml.data());
      glBindBuffer(GL_TEXTURE_BUFFER, 0);
      glActiveTexture(GL_TEXTURE0 + kCellsUnit);
      glBindTexture(GL_TEXTURE_BUFFER, cells_texture_);
      glActiveTexture(GL_TEXTURE0);
      scene_shader_.set("u_tool", 0.0F);
      glBindVertexArray(vessel_vao_);
      for (const auto& [first, count] : lit_runs_) {
        glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(count), GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(static_cast<std::size_t>(first) * sizeof(std::uint32_t)));
        work_.vessel_triangles += count / 3;
      }
      glBindVertexArray(0);
    }
    draw_tools();
    glDisable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  }
  glDisable(GL_SCISSOR_TEST);
  t.key = key;
  t.valid = true;
  ++work_.scenes_accumulated;
}

}  // namespace cathbox::app
