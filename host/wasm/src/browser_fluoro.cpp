#include "wasm/browser_fluoro.hpp"

#include <algorithm>
#include <cmath>

#include "app/fluoro_frontend.hpp"
#include "app/fluoro_image_model.hpp"
#include "flow/head_phantom.hpp"
#include "flow/xray_material.hpp"

namespace cathbox::wasm {
namespace {

std::uint64_t pose_key(const flow::CArmPose& p, int width, int height, double extra) {
  base::XxhHasher k;
  app::hash_pose(k, p);
  k.add(width);
  k.add(height);
  k.add(extra);
  return k.digest();
}

}  // namespace

bool BrowserFluoro::open(const session::Session& session) {
  const session::FluoroUnit* unit = session.fluoro();
  const vessel::SurfaceMesh* mesh = session.scene().mesh();
  if (unit == nullptr || mesh == nullptr) return false;
  // The native trainer draws the iodine on a surface one level coarser when it meshes the
  // vessel itself; here the surface comes made (the collision surface), as a native case with
  // its surface given.
  vessel_ = app::FluoroVessel::build(*mesh, unit->transport());
  cell_count_ = vessel_.cell_count;
  vessel_vertices_.clear();
  vessel_vertices_.reserve(6 * vessel_.positions_mm.size());
  for (std::size_t v = 0; v < vessel_.positions_mm.size(); ++v) {
    const glm::vec3& p = vessel_.positions_mm[v];
    const app::VertexCells& c = vessel_.cells[v];
    vessel_vertices_.insert(vessel_vertices_.end(), {p.x, p.y, p.z, static_cast<float>(c.a), static_cast<float>(c.b), c.w});
  }
  vessel_indices_.assign(vessel_.triangles.begin(), vessel_.triangles.end());
  return true;
}

void BrowserFluoro::project_phantom(const flow::CArm& carm, int width, int height, double l_ref) {
  // As FluoroRenderer::project_phantom: L and sqrt(T_ref / T) = exp((L - L_ref) / 2) per pixel,
  // bottom row first (as GL textures are filled).
  const std::vector<float> path = flow::HeadPhantom::neuro().project(carm, width, height);
  image_.phantom.resize(2 * path.size());
  const auto w = static_cast<std::size_t>(width);
  const auto h = static_cast<std::size_t>(height);
  for (std::size_t i = 0; i < path.size(); ++i) {
    const std::size_t o = 2 * ((h - 1 - i / w) * w + i % w);
    image_.phantom[o] = path[i];
    image_.phantom[o + 1] = static_cast<float>(std::exp(0.5 * (path[i] - l_ref)));
  }
}

void BrowserFluoro::pack_scenes(const app::FluoroInputs& in, double patient_pixel_mm, double keV) {
  image_.scene_floats.clear();
  image_.scene_indices.clear();
  const app::FluoroScene* scenes[] = {&in.shown, &in.mask, &in.roadmap, &in.roadmap_mask};
  for (int s = 0; s < 4; ++s) {
    const app::FluoroScene& scene = *scenes[s];
    const bool cells = scene.cell_iodine_mgI_ml.size() == cell_count_ && cell_count_ > 0;
    if (cells) image_.scene_floats.insert(image_.scene_floats.end(), scene.cell_iodine_mgI_ml.begin(), scene.cell_iodine_mgI_ml.end());
    tools_.build(scene, patient_pixel_mm, keV);
    image_.scene_floats.insert(image_.scene_floats.end(), tools_.vertices().begin(), tools_.vertices().end());
    image_.scene_indices.insert(image_.scene_indices.end(), tools_.indices().begin(), tools_.indices().end());
    image_.header[kScenes + 3 * s] = cells ? static_cast<double>(cell_count_) : 0.0;
    image_.header[kScenes + 3 * s + 1] = static_cast<double>(tools_.vertices().size());
    image_.header[kScenes + 3 * s + 2] = static_cast<double>(tools_.indices().size());
  }
}

void BrowserFluoro::frame(const session::SceneSnapshot& snapshot, int width, int height) {
  const app::FluoroInputs in = app::fluoro_inputs_from_snapshot(snapshot, {});
  const app::FluoroDisplay display;
  const flow::CArm carm(in.pose);
  const bool has_image = app::check_fluoro_inputs(in, cell_count_).empty() && in.image.pulse >= 0 && in.shown.pulse >= 0;
  const bool subtracted = has_image && in.image.subtracted() && in.mask.pulse >= 0;
  const bool roadmap = has_image && !subtracted && in.image.roadmap_pulse >= 0 && in.roadmap.pulse >= 0 && in.roadmap_mask.pulse >= 0;
  const double pitch = in.shown.mode == flow::ExposureMode::kFluoroscopy ? display.fluoro_readout_pitch_mm : 0.0;
  const app::ImageMatrix m = app::readout_matrix(width, height, carm.pixel_mm(width, height), pitch);
  const double l_ref = -std::log(std::clamp(in.patient_transmission, 1e-9, 1.0));
  const double keV = in.dose.effective_keV;
  const double pixel_mm = carm.pixel_mm(m.width, m.height);
  image_.header[kHasImage] = has_image ? 1.0 : 0.0;
  image_.header[kPulse] = static_cast<double>(in.shown.pulse);
  image_.header[kSubtracted] = subtracted ? 1.0 : 0.0;
  image_.header[kRoadmap] = roadmap ? 1.0 : 0.0;
  image_.header[kWidth] = m.width;
  image_.header[kHeight] = m.height;
  image_.header[kLRef] = l_ref;
  image_.header[kIodineMu] = flow::iodine_per_mm_per_mgI_ml(keV);
  const double sod = carm.depth_mm(carm.isocenter_mm());
  image_.header[kSod] = sod;
  const glm::dvec3 source = carm.source_mm();
  image_.header[kSourceX] = source.x;
  image_.header[kSourceY] = source.y;
  image_.header[kSourceZ] = source.z;
  image_.header[kFieldHalf] = 0.5 * std::min(m.width, m.height) * in.pose.collimation;
  const flow::FluoroDose dose(in.dose);
  const app::FluoroScene* scenes[] = {&in.shown, &in.mask, &in.roadmap, &in.roadmap_mask};
  for (int s = 0; s < 4; ++s) {
    image_.header[kSigma + s] = display.noise ? dose.log_noise_sigma(scenes[s]->mode, pixel_mm) : 0.0;
    image_.header[kSeeds + s] = app::pulse_seed(scenes[s]->pulse);
  }
  const float shown[] = {display.fluoro_slope, display.dsa_background, display.dsa_gain, display.roadmap_gain, display.anatomy_gain};
  std::copy(std::begin(shown), std::end(shown), image_.header.begin() + kDisplay);
  const glm::mat4 vp = carm.projection_matrix(m.width, m.height, 0.25 * sod, carm.pose().sid_mm) * carm.view_matrix();
  for (int i = 0; i < 16; ++i) image_.header[kViewProj + i] = vp[i / 4][i % 4];
  // The phantom is projected for a pose and size before its first pulse (the worker asks at
  // open, before its clock starts: a projection is tens of ms of CPU).
  if (const std::uint64_t key = pose_key(in.pose, m.width, m.height, l_ref); key != phantom_key_) {
    project_phantom(carm, m.width, m.height, l_ref);
    phantom_key_ = key;
    image_.header[kPhantomVersion] += 1.0;
  }
  if (!has_image) return;
  if (const std::uint64_t key = pose_key(in.pose, m.width, m.height, static_cast<double>(snapshot.fluoro.inputs_version));
      key != scene_key_) {
    pack_scenes(in, pixel_mm / carm.magnification(carm.isocenter_mm()), keV);
    scene_key_ = key;
    image_.header[kSceneVersion] += 1.0;
  }
}

}  // namespace cathbox::wasm
