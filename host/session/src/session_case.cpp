#include "session/session_case.hpp"

#include <algorithm>
#include <filesystem>
#include <optional>

#include <glm/geometric.hpp>

#include "base/read_file.hpp"
#include "scenario/case_clots.hpp"
#include "scenario/case_surface.hpp"
#include "tool/mesh_wall.hpp"

namespace cathbox::session {
namespace {

constexpr std::uintmax_t kMaxCaseBytes = 16u << 20;
constexpr std::uintmax_t kMaxVesselBytes = 64u << 20;

// A case text of at most `limit` bytes, or "path:0: what".
base::Result<std::string> read_case_text(const std::string& path, std::uintmax_t limit) {
  base::Result<std::string, base::ReadFileError> text = base::read_file(path, limit);
  if (text) return std::move(*text);
  if (text.error().kind == base::ReadFileError::Kind::kCannotOpen) return base::Error{path + ":0: cannot open file"};
  return base::Error{path + ":0: file of " + std::to_string(text.error().size_bytes) + " bytes is too large"};
}

std::vector<PathSegment> path_segments(const vessel::VesselModel& model) {
  std::vector<PathSegment> out(model.segments.size());
  for (std::size_t i = 0; i < model.segments.size(); ++i) {
    const vessel::Segment& s = model.segments[i];
    for (const vessel::CenterlinePoint& p : s.points) out[i].points_mm.push_back(glm::vec3(p.pos_mm));
    for (std::int32_t id : s.parents) {
      if (const auto k = model.index_of(id)) out[i].parents.push_back(*k);
    }
    for (std::int32_t id : s.children) {
      if (const auto k = model.index_of(id)) out[i].children.push_back(*k);
    }
  }
  return out;
}

double radius_near(const vessel::VesselModel& model, const glm::vec3& p) {
  double best_d = 1e300;
  double r = 1.0;
  for (const vessel::Segment& s : model.segments) {
    for (const vessel::CenterlinePoint& q : s.points) {
      const double d = static_cast<double>(glm::distance(glm::vec3(q.pos_mm), p));
      if (d < best_d) {
        best_d = d;
        r = q.radius_mm;
      }
    }
  }
  return r;
}

// What the session derives from the built world.
SessionCaseLoad finish(std::unique_ptr<SessionCase> c, const std::string& source, const vessel::SurfaceMesh* surface) {
  // The case's own wall, from the bytes kept for the record (none handed in).
  std::optional<vessel::SurfaceMesh> own;
  if (surface == nullptr && !c->surface_bytes.empty()) {
    base::Result<vessel::SurfaceMesh> decoded = tool::decode_case_surface(c->surface_bytes, c->surface_file);
    if (!decoded) {
      return base::Error{decoded.error().message};
    }
    own = std::move(*decoded);
    surface = &*own;
  }
  tool::WorldBuild built = tool::build_world(c->spec, c->vessel_text, surface);
  if (!built) {
    return base::Error{built.error().message};
  }
  c->world = std::move(*built);
  c->entry = c->world->entry();
  if (c->name.empty()) c->name = c->spec.name.empty() ? std::filesystem::path(source).filename().string() : c->spec.name;
  c->wall_force_threshold_mN = c->spec.wall_force_threshold_mN.value_or(100.0);
  const vessel::VesselModel* model = c->world->model();
  if (model == nullptr) {  // analytic tubes: no centreline graph
    if (c->world->target()) c->target_mm = glm::vec3(*c->world->target());
    return c;
  }
  // The blood flow over the vessel network (the case's `flow` overrides): the fluoroscopy
  // unit's contrast rides on it. A case file the flow model refuses is bad input (a bad override
  // names its line); a bare vessel file it cannot solve runs without fluoroscopy, saying why.
  flow::FlowBuild network = flow::FlowNetwork::build(*model, c->spec.flow);
  if (network) {
    c->flow = std::move(*network);
    // The case's clots occlude their branches (sim/flow, "Clots"): the contrast stops at them.
    const auto clots = tool::resolve_clots(c->spec, *model);
    if (!clots) {
      return base::Error{clots.error().message};
    }
    if (!clots->empty()) {
      if (base::Status<> occluded = c->flow->occlude(*clots); !occluded) {
        return base::Error{source + ": " + occluded.error().message};
      }
    }
  } else if (!c->case_file.empty()) {
    return base::Error{network.error().message};
  } else {
    c->flow_error = network.error().message;
  }
  c->segments = path_segments(*model);
  const PathPoint from = CenterlinePath::nearest(c->segments, glm::vec3(c->entry.point_mm));
  std::optional<PathPoint> goal;
  if (c->spec.target) {
    const auto index = model->index_of(c->spec.target->segment);
    if (!index) {
      return base::Error{source + ": target segment " + std::to_string(c->spec.target->segment) + " is not in " + c->vessel_file};
    }
    goal = PathPoint{*index, c->spec.target->fraction};
    c->target_mm = CenterlinePath::point_at(c->segments[*index], c->spec.target->fraction);
    c->target_radius_mm = static_cast<float>(std::clamp(radius_near(*model, *c->target_mm), 1.5, 4.0));
  } else {
    goal = CenterlinePath::farthest_leaf(c->segments, from);
  }
  if (goal) {
    std::vector<std::size_t> along;
    c->route_mm = CenterlinePath::between(c->segments, from, *goal, &along);
    if (c->spec.target && !c->route_mm.empty()) {
      c->route_length_mm = CenterlinePath::length_mm(c->route_mm);
      for (const std::size_t i : along) c->route_segment_ids.push_back(model->segments[i].id);
    }
  }
  return c;
}

}  // namespace

std::optional<glm::vec3> SessionCase::pick(const glm::vec3& origin_mm, const glm::vec3& direction) const {
  const auto* wall = world ? dynamic_cast<const tool::MeshWall*>(&world->wall()) : nullptr;
  if (wall == nullptr) return std::nullopt;
  const auto hit = wall->tree().ray_cast(glm::dvec3(origin_mm), glm::dvec3(direction));
  if (!hit) return std::nullopt;
  return glm::vec3(hit->point_mm);
}

SessionCaseLoad load_session_case(const std::string& path, const vessel::SurfaceMesh* surface) {
  auto c = std::make_unique<SessionCase>();
  // A file's bytes into one of the case's texts; false with the error line in `why`.
  std::optional<base::Error> why;
  const auto read_into = [&why](base::Result<std::string> read, std::string& text) {
    if (!read) {
      why = read.error();
      return false;
    }
    text = std::move(*read);
    return true;
  };
  if (std::filesystem::path(path).extension() == ".hclm") {
    // A bare vessel file: the default guidewire from the start of the root segment.
    c->spec.name = std::filesystem::path(path).stem().string();
    c->spec.vessel_path = path;
    c->spec.tools = {tool::default_guidewire()};
  } else {
    if (!read_into(read_case_text(path, kMaxCaseBytes), c->case_text)) return *why;
    tool::CaseParse parsed = tool::parse_case(c->case_text, path);
    if (!parsed) return base::Error{parsed.error().message};
    c->case_file = path;
    c->spec = std::move(*parsed);
  }
  c->vessel_file = c->spec.vessel_path;
  if (!c->vessel_file.empty() && !read_into(read_case_text(c->vessel_file, kMaxVesselBytes), c->vessel_text)) return *why;
  c->surface_file = c->spec.surface_path;
  if (!c->surface_file.empty() && !read_into(tool::read_case_surface_bytes(c->surface_file), c->surface_bytes)) return *why;
  return finish(std::move(c), path, surface);
}

SessionCaseLoad session_case_from_record(const RecordHeader& h, const vessel::SurfaceMesh* surface) {
  auto c = std::make_unique<SessionCase>();
  if (!h.case_text.empty()) {
    tool::CaseParse parsed = tool::parse_case(h.case_text, h.case_file);
    if (!parsed) {
      return base::Error{"the record's case: " + parsed.error().message};
    }
    c->spec = std::move(*parsed);
    c->case_file = h.case_file;
    c->case_text = h.case_text;
  } else {
    c->spec.name = h.case_name;
  }
  // The vessel, the tools and the entry as recorded.
  c->spec.vessel_path = h.vessel_file;
  c->spec.tools = h.tools;
  tool::steer_aspiration_catheters(c->spec);  // derived from the case text's `aspiration` lines
  c->spec.entry = h.entry;
  c->name = h.case_name;
  c->vessel_file = h.vessel_file;
  c->vessel_text = h.vessel_text;
  // The wall as recorded: the case's surface bytes, whatever the file holds now.
  c->spec.surface_path = h.surface_file;
  c->surface_file = h.surface_file;
  c->surface_bytes = h.surface_bytes;
  if (!c->surface_file.empty() && c->surface_bytes.empty()) {
    return base::Error{"the record names a surface (" + h.surface_file + ") but carries none of its bytes"};
  }
  if (c->spec.vessel_path.empty() && c->spec.tubes.empty()) {
    return base::Error{"the record carries neither a vessel file nor analytic tubes"};
  }
  return finish(std::move(c), h.case_file.empty() ? h.vessel_file : h.case_file, surface);
}

}  // namespace cathbox::session
