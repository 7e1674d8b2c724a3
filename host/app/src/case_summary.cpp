#include "app/case_summary.hpp"

#include <filesystem>
#include <string>

#include <glm/geometric.hpp>

#include "base/read_file.hpp"
#include "scenario/case_file.hpp"
#include "session/centerline_path.hpp"
#include "vessel/hclm.hpp"

namespace cathbox::app {
namespace {

constexpr std::uintmax_t kMaxCaseBytes = 16U << 20U;

// The vessel file's centreline and, when the case names one, the target on it; the number of
// segments read.
std::size_t add_vessel(const std::string& hclm_path, const std::optional<tool::CaseTarget>& target, CaseSummary& out) {
  const vessel::HclmReadResult read = vessel::load_hclm(hclm_path);
  if (!read.ok()) {
    out.error = read.errors.front().to_string();
    return 0;
  }
  out.tubes = centreline_tubes(read.model);
  if (!target) return read.model.segments.size();
  for (const vessel::Segment& s : read.model.segments) {
    if (s.id != target->segment || s.points.empty()) continue;
    session::PathSegment path;
    for (const vessel::CenterlinePoint& p : s.points) path.points_mm.emplace_back(p.pos_mm);
    out.target_mm = glm::dvec3(session::CenterlinePath::point_at(path, target->fraction));
  }
  return read.model.segments.size();
}

// A description that opens with the title (the library's "library: X (generated: ...)") without
// it: the row shows the title above.
std::string without_title(const std::string& description, const std::string& title) {
  if (title.empty() || !description.starts_with(title)) return description;
  std::size_t i = title.size();
  while (i < description.size() && description[i] == ' ') ++i;
  if (i < description.size() && description[i] == '(') {
    const std::size_t close = description.find(')', i);
    i = close == std::string::npos ? description.size() : close + 1;
  }
  while (i < description.size() && (description[i] == ' ' || description[i] == '.' || description[i] == ':')) ++i;
  return description.substr(i);
}

CaseSummary summarise_case_file(const std::string& path) {
  CaseSummary out;
  out.title = std::filesystem::path(path).filename().string();
  const base::Result<std::string, base::ReadFileError> text = base::read_file(path, kMaxCaseBytes);
  if (!text) {
    out.error = path + ": cannot read the file (missing, unreadable or larger than 16 MiB)";
    return out;
  }
  out.description = first_comment_block(*text);
  const tool::CaseParse parsed = tool::parse_case(*text, path);
  if (!parsed) {
    out.error = parsed.error().message;
    return out;
  }
  if (!parsed->name.empty()) out.title = parsed->name;
  out.description = without_title(out.description, out.title);
  if (!parsed->vessel_path.empty()) {
    (void)add_vessel(parsed->vessel_path, parsed->target, out);
    return out;
  }
  out.tubes = parsed->tubes;
  return out;
}

}  // namespace

std::string first_comment_block(std::string_view text) {
  std::string out;
  bool in_block = false;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
    if (line.empty() || line.front() != '#') {
      if (in_block) break;
      continue;
    }
    in_block = true;
    line.remove_prefix(1);
    while (!line.empty() && line.front() == ' ') line.remove_prefix(1);
    if (line.empty()) continue;
    if (!out.empty()) out += ' ';
    out += line;
  }
  return out;
}

std::vector<ThumbnailTube> centreline_tubes(const vessel::VesselModel& model) {
  std::vector<ThumbnailTube> tubes;
  for (const vessel::Segment& s : model.segments) {
    for (std::size_t i = 0; i + 1 < s.points.size(); ++i) {
      tubes.push_back({s.points[i].pos_mm, s.points[i + 1].pos_mm, s.points[i].radius_mm, s.points[i + 1].radius_mm, s.id});
    }
    // A child that starts off its parent's end is joined to it, as the mesher's junction joins them.
    if (s.points.empty()) continue;
    for (const std::int32_t parent_id : s.parents) {
      const std::optional<std::size_t> pi = model.index_of(parent_id);
      if (!pi || model.segments[*pi].points.empty()) continue;
      const vessel::CenterlinePoint& end = model.segments[*pi].points.back();
      if (glm::length(end.pos_mm - s.points.front().pos_mm) > 0.0) {
        tubes.push_back({end.pos_mm, s.points.front().pos_mm, end.radius_mm, s.points.front().radius_mm, s.id});
      }
    }
  }
  return tubes;
}

CaseSummary read_case_summary(const std::string& path) {
  if (std::filesystem::path(path).extension() != ".hclm") return summarise_case_file(path);
  CaseSummary out;
  out.title = std::filesystem::path(path).filename().string();
  const std::size_t segments = add_vessel(path, std::nullopt, out);
  if (out.error.empty()) {
    out.description = "Vessel file (HCLM), " + std::to_string(segments) +
                      " segments: the default guidewire from the start of the root segment, no target.";
  }
  return out;
}

}  // namespace cathbox::app
