#pragma once
// The fluoroscopic view: turns FluoroInputs into the grey image on the monitor of an
// angiography suite (OpenGL 3.3 core, the trainer's context). docs/trainer/fluoroscopy.md, "The
// fluoroscopic view", describes the image model; in short:
//
// - Every pixel is a ray from the focal spot through the C-arm geometry (flow::CArm) and its
//   Beer-Lambert exponent L = sum of mu * path: the head-and-neck phantom's (exact chords,
//   projected on the CPU once per pose and size), plus the iodine in the lumen and the tools,
//   accumulated on the GPU into a float target by front/back-face depth: each face of a closed
//   mesh adds sign * mu * distance from the source (entering faces negative), so a ray's sum is
//   mu times its path inside. The vessel's mu comes per vertex from the pulse's per-cell iodine
//   (a buffer texture); the accumulation also keeps sum(sign mu), sum(sign d) and
//   sum(sign d^2) so that mu varying between a chord's entry and exit integrates as the
//   trapezoid. Tools are closed tubes of their material, thinner ones widened to a pixel with
//   mu scaled to keep their attenuation across the line; marker bands are platinum.
// - The monitor: log transmission through a sigmoid window around the dose control's reference
//   transmission, plus quantum noise of the pulse's dose (flow::FluoroDose) from a hash of
//   pixel and pulse number (deterministic per pulse, fluoro_image_model.hpp); digital
//   subtraction (run frame minus its mask); the roadmap (peak subtraction frame) added onto live
//   fluoroscopy; black outside the collimated field and before the first pulse.
// - The detector's readout: fluoroscopy is made at the binned readout's pixels
//   (FluoroDisplay::fluoro_readout_pitch_mm, 0.4 mm at the detector) where a display pixel is
//   finer, and scaled to the viewport bilinearly on its way to the window; subtraction runs at
//   the display's pixels. Everything per pixel (phantom, scenes, noise, thin lines, field)
//   follows the image's own pixel size.
// - Each of the four scenes (shown, mask, roadmap, roadmap mask) is accumulated once and kept
//   while its inputs, the pose and the size stay the same, and the composed monitor image is
//   kept until one of them, a pulse number or the display changes: last-image hold and the
//   display frames between pulses only copy it.
// - Only the part of a scene target that its tools and iodine-filled vessel triangles can cover
//   (the 64-pixel cells their screen boxes touch, from the tools' nodes and each vessel bucket's
//   box) is cleared, drawn and read: the composite outside the scenes' cells reads the phantom
//   alone (on llvmpipe every texel fetch of a full-frame pass costs ~8 ms of CPU at 1024^2);
//   with GL_EXT_shader_framebuffer_fetch the phantom is read from the framebuffer instead.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "app/fluoro_image_model.hpp"
#include "app/fluoro_inputs.hpp"
#include "app/fluoro_vessel.hpp"
#include "app/phantom_projections.hpp"
#include "app/shader_program.hpp"
#include "app/fluoro_tool_mesh.hpp"
#include "app/viewport.hpp"
#include "base/result.hpp"
#include "flow/head_phantom.hpp"

namespace cathbox::app {

class FluoroRenderer {
 public:
  FluoroRenderer() = default;
  ~FluoroRenderer();
  FluoroRenderer(const FluoroRenderer&) = delete;
  FluoroRenderer& operator=(const FluoroRenderer&) = delete;

  // Compiles the shaders and makes the buffers; or the driver's log as the error.
  // `framebuffer_fetch`: read the phantom in the composite through GL_EXT_shader_framebuffer_fetch
  // when the driver has it (false: always as a texture; tests compare the two).
  [[nodiscard]] base::Status<> init(bool framebuffer_fetch = true);
  [[nodiscard]] bool uses_framebuffer_fetch() const { return fbfetch_; }
  void set_phantom(flow::HeadPhantom phantom);  // default: HeadPhantom::neuro()
  // The vessel whose lumen holds the contrast (uploaded; the cell layout of the transport the
  // scenes' cell_iodine come from). Without one, contrast is not drawn.
  void set_vessel(const FluoroVessel& vessel);
  // set_vessel() in two steps, for a vessel that changes while it is shown (a balloon widened
  // the lumen): prepare_vessel() does the CPU work without GL (any thread), upload_vessel()
  // only hands the buffers to GL and marks the scenes stale (the render thread).
  struct Bucket {
    std::uint32_t first_index = 0;
    std::uint32_t index_count = 0;
    std::uint32_t lo = 0;  // the lowest and highest contrast cell its vertices read
    std::uint32_t hi = 0;
    glm::vec3 box_min{0.0F};  // its vertices' bounding box (mm)
    glm::vec3 box_max{0.0F};
  };
  struct VesselBuffers {
    std::vector<float> vertices;         // x, y, z, cell a, cell b, weight per vertex
    std::vector<std::uint32_t> indices;  // the triangles, sorted into buckets
    std::vector<Bucket> buckets;
    std::size_t cell_count = 0;
  };
  [[nodiscard]] static VesselBuffers prepare_vessel(const FluoroVessel& vessel);
  void upload_vessel(VesselBuffers buffers);
  void set_display(const FluoroDisplay& display) { display_ = display; }
  // On (the interactive trainer): when the C-arm moves, the phantom is projected on a worker
  // thread and render() shows the last image until it is ready, so a move does not stall the
  // frames (~150 ms of CPU at 1024^2). Off (the default: tests, headless runs): at once.
  void set_background_projection(bool on) { projections_.set_background(on); }
  // Blocks until the background projection under way (if any) is done; the next render() uses it.
  // The projection of the other readout at a new pose (see project_phantom) is waited for too.
  void finish_projection() { projections_.finish(); }
  [[nodiscard]] const FluoroDisplay& display() const { return display_; }

  // Draws the monitor image into `viewport` of the bound framebuffer (the image is
  // viewport.width x viewport.height pixels, the detector field across the shorter side).
  // Inputs that check_fluoro_inputs() refuses draw a black image and return its one line.
  [[nodiscard]] std::string render(const Viewport& viewport, int framebuffer_height, const FluoroInputs& inputs);

  // What the last render() had to redo (for tests and the bench).
  struct Work {
    bool phantom_projected = false;
    int scenes_accumulated = 0;
    int composites = 0;                // the monitor image made again (else copied)
    std::size_t vessel_triangles = 0;  // drawn into scene targets (those reading cells with iodine)
    bool waiting_for_phantom = false;  // background projection under way: the last image shown
    int matrix_width = 0;              // the image's pixels (the readout; the viewport's when not binned)
    int matrix_height = 0;
  };
  [[nodiscard]] const Work& last_work() const { return work_; }

 private:
  // A rectangle of a target in GL pixels (origin bottom left), [x0, x1) x [y0, y1).
  struct Rect {
    int x0 = 0;
    int y0 = 0;
    int x1 = 0;
    int y1 = 0;
    [[nodiscard]] bool empty() const { return x1 <= x0 || y1 <= y0; }
  };
  // Cells of 64 x 64 pixels (llvmpipe's tiles) of a target, each on or off.
  struct CellMask {
    static constexpr int kCell = 64;
    int width = 0;
    int height = 0;
    std::vector<unsigned char> on;
    void reset(int w, int h, bool value);
    void mark(const Rect& r);  // every cell r touches
    void unite(const CellMask& other);
    [[nodiscard]] Rect bounds() const;
    // The cells equal to `value` as rectangles (runs along rows, joined with identical runs of
    // the rows above), clipped to the target.
    [[nodiscard]] std::vector<Rect> runs(bool value) const;
  };
  struct Target {
    CellMask drawn;  // where this scene's content may be non-zero (outside it: zero)
    CellMask dirty;  // where the texture may hold anything but zero
    unsigned texture = 0;
    unsigned fbo = 0;
    int width = 0;
    int height = 0;
    std::uint64_t key = 0;
    bool valid = false;
  };
  class ScreenBox;
  struct Matrix {
    int width = 0;
    int height = 0;
  };
  // The image's pixels for a viewport: fewer than the viewport's when the detector's readout
  // (fluoroscopy: FluoroDisplay::fluoro_readout_pitch_mm) is coarser than a display pixel.
  [[nodiscard]] Matrix matrix(const flow::CArm& carm, int width, int height, flow::ExposureMode mode) const;
  static Rect unite(const Rect& a, const Rect& b);
  static void ensure_target(Target& t, int width, int height, unsigned internal_format, unsigned type);
  // `source` scaled bilinearly into the rectangle (x, y, width, height) of framebuffer `fbo`
  // (the scale shader: cheaper than glBlitFramebuffer on llvmpipe).
  void scale(const Target& source, unsigned fbo, int x, int y, int width, int height);
  void compose(const FluoroInputs& in, const flow::CArm& carm, bool subtracted, bool roadmap, int width, int height);
  // What the monitor shows beside the live scene.
  struct Shown {
    bool subtracted = false;  // a subtraction run's image (the mask scene subtracted)
    bool roadmap = false;     // the roadmap (and its mask) over the live image
  };
  struct SavedGlState;
  void update_monitor(const FluoroInputs& in, const flow::CArm& carm, const Shown& shown, const Matrix& m);
  [[nodiscard]] std::uint64_t monitor_key(const FluoroInputs& in, const Shown& shown) const;
  void show_monitor(const Viewport& viewport, int gl_y, unsigned fbo);
  void accumulate(Target& target, const FluoroScene& scene, const flow::CArm& carm, double keV, int width, int height);
  // Fills tool_mesh_ and returns the tools' screen box; draw_tools draws them.
  Rect build_tools(const FluoroScene& scene, const flow::CArm& carm, double keV, int width, int height);
  CellMask scenes_;  // compose: the union of the shown scenes' cells
  CellMask drawn_;   // accumulate: the cells this scene draws in
  void draw_tools();
  // False while a background projection for this pose is under way (nothing to draw with yet).
  // `other`: the other readout's size at this pose (a run's full one during binned fluoroscopy,
  // and back), projected in the background after a pose's first projection.
  bool project_phantom(const flow::CArm& carm, const Matrix& size, const Matrix& other, double l_ref);
  [[nodiscard]] std::uint64_t phantom_key(const flow::CArm& carm, const Matrix& size) const;

  FluoroDisplay display_;
  flow::HeadPhantom phantom_ = flow::HeadPhantom::neuro();
  std::uint64_t generation_ = 1;  // bumped by set_vessel / set_phantom: the targets are stale
  ShaderProgram scene_shader_;
  // Fluoroscopy, with the roadmap, subtraction; then the same three reading the phantom alone
  // (outside the scenes' box).
  std::array<ShaderProgram, 6> composite_shaders_;
  ShaderProgram scale_shader_;     // a binned image to the viewport, bilinear
  unsigned linear_sampler_ = 0;    // GL_LINEAR, clamped to the edge: the scale shader's
  unsigned empty_vao_ = 0;
  unsigned phantom_texture_ = 0;
  PhantomProjections projections_;  // the phantom's projections (current, spare, workers)
  double phantom_l_ref_ = -1.0;     // the noise reference the phantom texture was made for
  bool framebuffer_fetch_wanted_ = true;
  bool fbfetch_ = false;  // the composite reads the phantom as a colour attachment (compose_fbo_)
  unsigned compose_fbo_ = 0;  // the phantom texture and the monitor image, attached 0 and 1
  std::vector<float> phantom_rg_;
  std::array<Target, 4> targets_{};  // shown, mask, roadmap, roadmap mask
  Target monitor_;                   // the composed grey image (RGBA8)
  Target scaled_;                    // a binned monitor_ image scaled to the viewport (key: monitor_'s)
  std::uint64_t shown_key_ = 0;      // monitor_'s key when the last frame was shown
  int shows_ = 0;                    // frames in a row that showed it
  // The vessel: positions and (cell a, cell b, weight) per vertex, and the cells' iodine.
  unsigned vessel_vao_ = 0;
  unsigned vessel_vbo_ = 0;
  unsigned vessel_ebo_ = 0;
  std::size_t vessel_indices_ = 0;
  std::vector<Bucket> buckets_;              // the vessel's triangles, sorted by their lowest cell
  std::vector<std::uint32_t> nonzero_before_;  // per pulse: cells with iodine before each cell
  std::vector<std::pair<std::uint32_t, std::uint32_t>> lit_runs_;  // per scene: (first index, count) drawn
  std::size_t cell_count_ = 0;
  unsigned cells_buffer_ = 0;
  unsigned cells_texture_ = 0;
  // The tools, rebuilt for each accumulated scene.
  unsigned tools_vao_ = 0;
  unsigned tools_vbo_ = 0;
  unsigned tools_ebo_ = 0;
  std::size_t tools_vbo_bytes_ = 0;
  std::size_t tools_ebo_bytes_ = 0;
  FluoroToolMesh tool_mesh_;
  Work work_;
};

}  // namespace cathbox::app
