#include "app/fluoro_frontend.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include <glm/geometric.hpp>

#include "app/stent_view.hpp"
#include "flow/head_phantom.hpp"

namespace cathbox::app {

namespace {

// An expanded stent retriever as a device shows in fluoroscopy: the push wire up to the stent,
// then only the stent's platinum markers (its nitinol struts, ~0.07 mm wide and thick over a
// few % of the surface, attenuate the beam by ~2 % where a 0.36 mm wire takes ~50 %: below the
// image's noise, so not drawn): one on the axis where the cells join the push wire, and
// kStentDistalMarkers at the struts' distal ends, evenly round the expanded radius.
void add_expanded_stent(const session::ToolView& view, const std::vector<glm::vec3>& nodes, std::size_t split, std::vector<FluoroTool>& out) {
  FluoroTool wire;
  wire.nodes_mm.assign(nodes.begin(), nodes.begin() + static_cast<std::ptrdiff_t>(split) + 1);
  wire.radius_mm = view.wire_radius_mm;
  out.push_back(std::move(wire));
  const std::span<const glm::vec3> stent(nodes.data() + split, nodes.size() - split);
  const double length = polyline_length(stent);
  const auto marker = [&](double from_tip_mm, const glm::vec3& offset) {
    FluoroTool m;
    m.material = flow::XrayMaterial::kPlatinum;
    m.radius_mm = static_cast<float>(kStentMarkerRadius_mm);
    polyline_part(stent, length - from_tip_mm - kStentMarker_mm, length - from_tip_mm, m.nodes_mm);
    for (glm::vec3& p : m.nodes_mm) p += offset;
    if (m.nodes_mm.size() >= 2) out.push_back(std::move(m));
  };
  marker(std::max(0.0, length - kStentMarker_mm), glm::vec3(0.0F));
  // Round the tip's tangent: the node's frame if the view has one, else any normal.
  const glm::vec3 t = glm::normalize(stent.back() - stent[stent.size() - 2]);
  glm::vec3 n0 = view.frames.size() == nodes.size() ? view.frames.back() : glm::vec3(0.0F);
  n0 -= t * glm::dot(n0, t);
  if (glm::length(n0) < 1e-3F) n0 = glm::cross(t, std::abs(t.x) < 0.9F ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
  n0 = glm::normalize(n0);
  const glm::vec3 n1 = glm::cross(t, n0);
  const float r = std::max(0.0F, view.radius_mm - static_cast<float>(kStentMarkerRadius_mm));
  for (int k = 0; k < kStentDistalMarkers; ++k) {
    const float a = 6.2831853F * static_cast<float>(k) / static_cast<float>(kStentDistalMarkers);
    marker(0.0, r * (std::cos(a) * n0 + std::sin(a) * n1));
  }
}

std::vector<FluoroTool> tools_at(const session::SceneSnapshot& snapshot, const SnapshotFluoroSettings& settings,
                                 const std::array<std::vector<glm::vec3>, session::kMaxTools>* at_pulse, int count) {
  std::vector<FluoroTool> out;
  const int tools = std::min(count, session::SceneSnapshot::kMaxTools);
  for (int i = 0; i < tools; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const session::ToolView& view = snapshot.tools[k];
    FluoroTool tool;
    tool.nodes_mm = at_pulse != nullptr ? (*at_pulse)[k] : view.nodes_mm;
    tool.radius_mm = view.radius_mm;
    if (const float stent_mm = view.stent_length_mm; stent_mm > 0.0F) {
      if (const std::size_t split = expanded_stent_first_node(view, tool.nodes_mm); split > 0) {
        add_expanded_stent(view, tool.nodes_mm, split, out);
        continue;
      }
      // Crimped in its catheter: the struts packed round the wire; a band at each end.
      tool.markers.push_back({0.0, kStentMarker_mm, flow::XrayMaterial::kPlatinum});
      tool.markers.push_back({std::max(0.0, stent_mm - kStentMarker_mm), kStentMarker_mm, flow::XrayMaterial::kPlatinum});
    } else {
      tool.markers.push_back({0.0, settings.tip_marker_mm, flow::XrayMaterial::kPlatinum});
    }
    if (tool.nodes_mm.size() >= 2) out.push_back(std::move(tool));
  }
  return out;
}

// The released coils: platinum along their whole length (no marker bands), appended to `out`.
void add_coils(const session::SceneSnapshot& snapshot, const std::array<std::vector<glm::vec3>, session::kMaxReleasedCoils>* at_pulse,
               int count, std::vector<FluoroTool>& out) {
  const int coils = std::min({count, snapshot.coil_count, session::SceneSnapshot::kMaxCoils});
  for (int i = 0; i < coils; ++i) {
    const auto k = static_cast<std::size_t>(i);
    FluoroTool coil;
    coil.nodes_mm = at_pulse != nullptr ? (*at_pulse)[k] : snapshot.coils[k].nodes_mm;
    coil.radius_mm = snapshot.coils[k].radius_mm;
    coil.material = flow::XrayMaterial::kPlatinum;
    if (coil.nodes_mm.size() >= 2) out.push_back(std::move(coil));
  }
}

FluoroScene iodine_scene(std::int64_t pulse, const std::vector<float>& iodine) {
  FluoroScene scene;
  scene.pulse = pulse;
  scene.cell_iodine_mgI_ml = iodine;
  return scene;
}

}  // namespace

FluoroInputs fluoro_inputs_from_snapshot(const session::SceneSnapshot& snapshot, const SnapshotFluoroSettings& settings) {
  FluoroInputs in;
  if (const session::FluoroView& f = snapshot.fluoro; f.available) {
    in.pose = f.pose;
    in.image = f.image;
    in.patient_transmission = flow::HeadPhantom::neuro().central_transmission(flow::CArm(f.pose));
    in.shown.pulse = f.image.pulse;
    in.shown.mode = f.image.mode;
    in.shown.cell_iodine_mgI_ml = f.iodine_mgI_ml;
    in.shown.tools = tools_at(snapshot, settings, &f.pulse_tool_nodes_mm, f.pulse_tool_count);
    add_coils(snapshot, &f.pulse_coil_nodes_mm, f.pulse_coil_count, in.shown.tools);
    if (f.image.subtracted()) {
      in.mask = iodine_scene(f.image.mask_pulse, f.mask_iodine_mgI_ml);
      in.mask.mode = flow::ExposureMode::kSubtractionRun;
      in.mask.tools = in.shown.tools;  // subtraction removes the tools that did not move
    }
    if (f.image.roadmap_pulse >= 0) {
      in.roadmap = iodine_scene(f.image.roadmap_pulse, f.roadmap_iodine_mgI_ml);
      in.roadmap_mask = iodine_scene(f.image.roadmap_pulse, f.roadmap_mask_iodine_mgI_ml);
    }
    return in;
  }
  in.pose = settings.pose;
  in.patient_transmission = settings.patient_transmission;
  // Pedal held since the run started: pulse k at k / rate seconds; the image shows the last.
  const auto pulse = static_cast<std::int64_t>(std::floor(static_cast<double>(snapshot.sim_time_us) * 1e-6 * settings.pulse_rate_hz));
  in.image.pulse = pulse;
  in.image.pulse_time_us = std::llround(static_cast<double>(pulse) * 1e6 / settings.pulse_rate_hz);
  in.image.beam_on = true;
  in.shown.pulse = pulse;
  in.shown.tools = tools_at(snapshot, settings, nullptr, snapshot.tool_count);
  add_coils(snapshot, nullptr, snapshot.coil_count, in.shown.tools);
  return in;
}

}  // namespace cathbox::app
