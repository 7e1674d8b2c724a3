#pragma once
// What a case becomes at run time: the wall the tools touch and the entry. Analytic tubes give
// a TubeNetworkWall; an HCLM vessel gives the vessel surface in the collision tree (when the
// vessel and collision modules are built).
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "base/result.hpp"
#include "tool/aneurysm_sac.hpp"
#include "scenario/case_file.hpp"
#include "vessel/surface_mesh.hpp"
#include "vessel/vessel_model.hpp"
#include "tool/simulator.hpp"
#include "tool/wall_model.hpp"

namespace cathbox::collision {
class ObbTree;
}  // namespace cathbox::collision

namespace cathbox::tool {

class CaseWorld {
 public:
  CaseWorld(std::unique_ptr<WallModel> wall, const Entry& entry) : wall_(std::move(wall)), entry_(entry) {}
  [[nodiscard]] const WallModel& wall() const { return *wall_; }
  [[nodiscard]] const Entry& entry() const { return entry_; }
  // The target point (the case's target segment and fraction on the smoothed centreline).
  [[nodiscard]] const std::optional<glm::dvec3>& target() const { return target_; }
  void set_target(const glm::dvec3& point_mm) { target_ = point_mm; }
  // The vessel surface the wall was built from (for rendering); empty for analytic tubes.
  [[nodiscard]] const vessel::SurfaceMesh* mesh() const { return mesh_ ? mesh_.get() : nullptr; }
  void set_mesh(std::shared_ptr<const vessel::SurfaceMesh> mesh) { mesh_ = std::move(mesh); }
  // The smoothed vessel model the surface follows (centrelines, radii, segment graph); null for
  // analytic tubes.
  [[nodiscard]] const vessel::VesselModel* model() const { return model_ ? model_.get() : nullptr; }
  void set_model(std::shared_ptr<const vessel::VesselModel> model) { model_ = std::move(model); }
  // The aneurysm sac: the case's declared one, else the vessel's sac segment (aneurysm_sac.hpp);
  // none when neither gives one.
  [[nodiscard]] const std::optional<AneurysmSac>& sac() const { return sac_; }
  void set_sac(std::optional<AneurysmSac> sac) { sac_ = sac; }
  // The vessel model as read (before smoothing), which the surface is meshed from: a widened
  // lumen (angioplasty.hpp) is re-meshed from it. Null for analytic tubes.
  [[nodiscard]] const vessel::VesselModel* source_model() const { return source_ ? source_.get() : nullptr; }
  void set_source_model(std::shared_ptr<const vessel::VesselModel> model) { source_ = std::move(model); }
  // True when the wall is the case's own surface (`surface FILE`, e.g. an imported lumen), not
  // meshed from the centrelines: views show that surface as it is (no coarser re-mesh).
  [[nodiscard]] bool surface_given() const { return surface_given_; }
  void set_surface_given(bool given) { surface_given_ = given; }
  // Hands the wall over (the world is then empty).
  [[nodiscard]] std::unique_ptr<WallModel> release_wall() { return std::move(wall_); }

 private:
  std::unique_ptr<WallModel> wall_;
  Entry entry_;
  std::optional<glm::dvec3> target_;
  std::optional<AneurysmSac> sac_;
  std::shared_ptr<const vessel::SurfaceMesh> mesh_;
  std::shared_ptr<const vessel::VesselModel> model_;
  std::shared_ptr<const vessel::VesselModel> source_;
  bool surface_given_ = false;
};

// The world, or one line naming the file and what went wrong.
using WorldBuild = base::Result<std::unique_ptr<CaseWorld>>;

[[nodiscard]] WorldBuild build_world(const Case& c);
// The entry of a vessel case without an `entry` line: the start of the root segment of the
// smoothed model, along it, stepped in until well inside the lumen (`tree`: the vessel surface's).
// None when no segment is a root.
[[nodiscard]] std::optional<Entry> default_entry(const vessel::VesselModel& smoothed, const collision::ObbTree& tree);
// The same from the vessel file's text (c.vessel_path only names it in errors): a record
// replays the HCLM it carries, whatever the file on disk holds now. With `surface_made`, the
// vessel surface is that mesh (made natively and sent, vessel/mesh_wire.hpp) instead of meshed
// here: what the WebAssembly session does, which has no OpenSubdiv. A case naming a `surface`
// without `surface_made` reads it from c.surface_path.
[[nodiscard]] WorldBuild build_world(const Case& c, std::string_view vessel_text,
                                     const vessel::SurfaceMesh* surface_made = nullptr);

}  // namespace cathbox::tool
