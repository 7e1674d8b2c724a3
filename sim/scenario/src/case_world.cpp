#include "scenario/case_world.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <fstream>
#include <sstream>

#include <glm/geometric.hpp>

#include "tool/tube_network_wall.hpp"
#include "collision/obb_tree.hpp"
#include "tool/mesh_wall.hpp"
#include "scenario/case_surface.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::tool {

namespace {

// Point at a fraction of a segment's length along its centreline.
glm::dvec3 along(const vessel::Segment& s, double fraction) {
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < s.points.size(); ++i) total += glm::length(s.points[i + 1].pos_mm - s.points[i].pos_mm);
  double want = std::clamp(fraction, 0.0, 1.0) * total;
  for (std::size_t i = 0; i + 1 < s.points.size(); ++i) {
    const glm::dvec3 a = s.points[i].pos_mm;
    const glm::dvec3 b = s.points[i + 1].pos_mm;
    const double len = glm::length(b - a);
    if (want <= len && len > 0.0) return a + (b - a) * (want / len);
    want -= len;
  }
  return s.points.back().pos_mm;
}

}  // namespace

std::optional<Entry> default_entry(const vessel::VesselModel& smoothed, const collision::ObbTree& tree) {
  // The start of the root segment (the first without parents), along it.
  const vessel::Segment* root = nullptr;
  for (const vessel::Segment& s : smoothed.segments) {
    if (s.parents.empty() && s.points.size() >= 2) {
      root = &s;
      break;
    }
  }
  if (root == nullptr) return std::nullopt;
  Entry entry;
  entry.point_mm = root->points[0].pos_mm;
  entry.direction = glm::normalize(root->points[1].pos_mm - root->points[0].pos_mm);
  // The root's first point lies on its end cap: step in until well inside the lumen.
  const double inside = 0.5 * root->points[0].radius_mm;
  for (int i = 0; i < 40; ++i) {
    const std::optional<double> d = tree.signed_distance(entry.point_mm);
    if (d && *d < -inside) break;
    entry.point_mm += entry.direction * (0.25 * root->points[0].radius_mm);
  }
  return entry;
}

WorldBuild build_world(const Case& c) {
  if (!c.tubes.empty()) return build_world(c, {});
  std::ifstream in(c.vessel_path, std::ios::binary);
  if (!in) return base::Error{c.vessel_path + ":0: cannot open file"};
  std::ostringstream text;
  text << in.rdbuf();
  return build_world(c, text.str());
}

WorldBuild build_world(const Case& c, std::string_view vessel_text, const vessel::SurfaceMesh* surface_made) {
  if (!c.tubes.empty()) {
    auto wall = std::make_unique<TubeNetworkWall>(c.tubes);
    auto world = std::make_unique<CaseWorld>(std::move(wall), *c.entry);
    world->set_sac(c.aneurysm);
    return WorldBuild(std::move(world));
  }
  const vessel::HclmReadResult read = vessel::read_hclm(vessel_text, c.vessel_path);
  if (!read.ok()) return base::Error{read.errors.front().to_string()};
  std::optional<vessel::SurfaceMesh> own;  // the case's `surface`, when no surface was handed in
  if (surface_made == nullptr && !c.surface_path.empty()) {
    const base::Result<std::string> bytes = read_case_surface_bytes(c.surface_path);
    if (!bytes) return base::Error{bytes.error().message};
    base::Result<vessel::SurfaceMesh> decoded = decode_case_surface(*bytes, c.surface_path);
    if (!decoded) return base::Error{decoded.error().message};
    own = std::move(*decoded);
    surface_made = &*own;
  }
  if (surface_made != nullptr && !c.surface_path.empty()) {
    if (std::string wrong = check_surface_regions(*surface_made, read.model, c.surface_path); !wrong.empty()) {
      return base::Error{std::move(wrong)};
    }
  }
  vessel::VesselSurface surface =
      surface_made ? vessel::build_vessel_surface(read.model, *surface_made) : vessel::build_vessel_surface(read.model);
  if (!surface.ok()) return base::Error{c.vessel_path + ": " + surface.error};
  collision::TreeBuild tree = collision::ObbTree::build(surface.mesh);
  if (!tree) return base::Error{c.vessel_path + ":0: vessel surface rejected by the collision tree: " + tree.error().message};
  Entry entry;
  if (c.entry) {
    entry = *c.entry;
  } else if (const std::optional<Entry> fallback = default_entry(surface.smoothed, *tree)) {
    entry = *fallback;
  } else {
    return base::Error{c.vessel_path + ":0: the vessel has no root segment to enter"};
  }
  // The wall knows the surface and the centrelines it was built from: its lumen radius (a stent
  // retriever's expanded diameter, WallModel::lumen_radius_mm) reads them; the world shares them.
  auto drawn = std::make_shared<const WallSurface>(WallSurface{std::move(surface.smoothed), std::move(surface.mesh)});
  auto world = std::make_unique<CaseWorld>(std::make_unique<MeshWall>(*tree, MeshWall::kDefaultHintSlots, drawn), entry);
  world->set_sac(c.aneurysm ? c.aneurysm : find_sac(drawn->model, drawn->mesh));
  world->set_mesh(std::shared_ptr<const vessel::SurfaceMesh>(drawn, &drawn->mesh));
  world->set_surface_given(!c.surface_path.empty());
  if (c.target) {
    for (const vessel::Segment& s : drawn->model.segments) {
      if (s.id == c.target->segment) world->set_target(along(s, c.target->fraction));
    }
  }
  world->set_model(std::shared_ptr<const vessel::VesselModel>(drawn, &drawn->model));
  world->set_source_model(std::make_shared<const vessel::VesselModel>(read.model));
  return WorldBuild(std::move(world));
}

}  // namespace cathbox::tool
