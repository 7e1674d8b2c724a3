#pragma once
// The trainee page's fluoroscopy, its CPU half (the page's WebGL2 half: host/server/web/js/
// fluoro_view.js, the native FluoroRenderer's shaders ported). Made in the haptic worker from the
// session's newest SceneSnapshot by the native trainer's own code, compiled in from host/app's
// GL-free sources: fluoro_inputs_from_snapshot (the pulse shown, its run's mask, the roadmap; the
// tools at the pulse and their radio-opaque markers), FluoroVessel (every vertex of the lumen tied
// to the flow's contrast cells), FluoroToolMesh (the tools' closed tubes and their mu), the image
// model (readout binning, noise seeds, thin lines), and sim/flow's head phantom, C-arm and dose.
// What crosses to the page, as flat arrays (layouts below and in fluoro_view.js):
//   the vessel (once):     vertices x, y, z, cell a, cell b, weight; triangle indices
//   the phantom (per pose and image size): L and sqrt(T_ref / T) per pixel, bottom row first
//   each image (per pulse): a header of doubles; per scene (shown, mask, roadmap, roadmap mask)
//                           the iodine per cell and the tools' vertices (x, y, z, mu, 0, 0), indices
#include <array>
#include <cstdint>
#include <vector>

#include "app/fluoro_inputs.hpp"
#include "app/fluoro_tool_mesh.hpp"
#include "app/fluoro_vessel.hpp"
#include "session/session.hpp"

namespace cathbox::wasm {

// The image header's fields (doubles), as js/fluoro_view.js reads them.
enum FluoroHeader : int {
  kHasImage = 0,     // 1: a pulse to show (else the monitor is black)
  kPulse,            // the shown pulse
  kSubtracted,       // 1: a subtraction run's frame (the mask scene subtracted)
  kRoadmap,          // 1: the roadmap over live fluoroscopy
  kWidth,            // the image's pixels (the detector's binned readout in fluoroscopy)
  kHeight,
  kLRef,             // -ln(T_ref): the dose control's reference
  kIodineMu,         // 1/mm per mgI/mL at the beam's effective energy
  kSod,              // the isocentre's depth from the source (mm)
  kSourceX,          // the focal spot (mm)
  kSourceY,
  kSourceZ,
  kFieldHalf,        // half the collimated field (pixels)
  kSigma,            // 4: log-noise sigma of the scenes at the reference transmission
  kSeeds = kSigma + 4,    // 4: the scenes' pulse seeds
  kDisplay = kSeeds + 4,  // 5: slope, DSA background, DSA gain, roadmap gain, anatomy gain
  kViewProj = kDisplay + 5,  // 16: the C-arm's view-projection (column-major)
  kSceneVersion = kViewProj + 16,  // changes with every new scene data (a pulse, the pose, the size)
  kPhantomVersion,   // changes with every new phantom projection
  kScenes,           // 4 x 3: cells, tool floats, tool indices of each scene
  kHeaderSize = kScenes + 12,
};

// One image's data for the page: the header, the phantom, the scenes' floats and indices (the
// phantom and the scenes belong to the header's versions).
struct FluoroImage {
  std::array<double, kHeaderSize> header{};
  std::vector<float> phantom;
  std::vector<float> scene_floats;
  std::vector<std::uint32_t> scene_indices;
};

class BrowserFluoro {
 public:
  // The session's lumen tied to its fluoroscopy unit's cells; false when the case has no unit.
  bool open(const session::Session& session);
  [[nodiscard]] const std::vector<float>& vessel_vertices() const { return vessel_vertices_; }
  [[nodiscard]] const std::vector<std::uint32_t>& vessel_indices() const { return vessel_indices_; }

  // The image for a display of width x height pixels from the snapshot; the header, and the
  // phantom and the scenes made again only when they changed (their versions say so).
  void frame(const session::SceneSnapshot& snapshot, int width, int height);
  [[nodiscard]] const FluoroImage& image() const { return image_; }

 private:
  void project_phantom(const flow::CArm& carm, int width, int height, double l_ref);
  void pack_scenes(const app::FluoroInputs& in, double patient_pixel_mm, double keV);

  std::size_t cell_count_ = 0;
  app::FluoroVessel vessel_;
  std::vector<float> vessel_vertices_;
  std::vector<std::uint32_t> vessel_indices_;
  app::FluoroToolMesh tools_;
  FluoroImage image_;
  std::uint64_t phantom_key_ = 0;
  std::uint64_t scene_key_ = 0;
};

}  // namespace cathbox::wasm
