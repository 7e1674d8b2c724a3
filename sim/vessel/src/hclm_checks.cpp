// The HCLM model's checks: each segment's own fields, its parent and child links, the gap from a
// parent's last point to a child; run by the reader on each file and by validate_model().
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "base/text_tokens.hpp"
#include "hclm_checks.hpp"
#include "vessel/hclm.hpp"
#include "vessel/point_range.hpp"

namespace cathbox::vessel {
namespace detail {
namespace {

using base::text::trim;

// One segment's own fields: point count, point ranges and radii, flow, name.
void check_segment_fields(const Segment& s, int line_g, int line_n, ErrorSink& sink) {
  if (s.points.size() < 2) {
    sink.add(line_n, "segment " + std::to_string(s.id) + " has " + std::to_string(s.points.size()) +
                         " points; at least 2 are needed");
  }
  for (std::size_t k = 0; k < s.points.size(); ++k) {
    const CenterlinePoint& p = s.points[k];
    if (std::string problem = point_range_problem(p.pos_mm, p.radius_mm); !problem.empty()) {
      sink.add(line_n, "segment " + std::to_string(s.id) + " point " + std::to_string(k) + ": " + problem);
      break;
    }
    if (!(p.radius_mm > 0.0)) {
      sink.add(line_n, "segment " + std::to_string(s.id) + " has a radius <= 0");
      break;
    }
  }
  if (!std::isfinite(s.flow)) sink.add(line_g, "flow is not finite");
  for (char ch : s.name) {
    if (static_cast<unsigned char>(ch) < 0x20) {
      sink.add(line_g, "segment name contains a control character");
      break;
    }
  }
  if (s.name != trim(s.name)) sink.add(line_g, "segment name has surrounding spaces");
}

// A child starts at or near its parent's last point.
void check_child_gap(const Segment& parent, const Segment& child, int line, ErrorSink& sink) {
  if (parent.points.empty() || child.points.empty()) return;
  const CenterlinePoint& end = parent.points.back();
  const CenterlinePoint& start = child.points.front();
  const double gap_mm = glm::length(end.pos_mm - start.pos_mm);
  const double limit_mm = 3.0 * std::max(end.radius_mm, start.radius_mm);
  if (std::isfinite(gap_mm) && gap_mm > limit_mm) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "child %d starts %.3g mm from the last point of %d (more than 3 radii)", child.id,
                  gap_mm, parent.id);
    sink.add(line, buf);
  }
}

// A segment's parent or child list: no self, no repeats, known ids, listed back, children near.
void check_links(const VesselModel& model, const std::unordered_map<std::int32_t, std::size_t>& index, const Segment& s,
                 bool parents, int line, ErrorSink& sink) {
  const std::vector<std::int32_t>& list = parents ? s.parents : s.children;
  const char* what = parents ? "parent" : "child";
  std::vector<std::int32_t> seen;
  for (std::int32_t other_id : list) {
    if (other_id == s.id) {
      sink.add(line, "segment " + std::to_string(s.id) + " lists itself as " + what);
      continue;
    }
    if (std::find(seen.begin(), seen.end(), other_id) != seen.end()) {
      sink.add(line, std::string(what) + " id " + std::to_string(other_id) + " listed twice");
      continue;
    }
    seen.push_back(other_id);
    const auto it = index.find(other_id);
    if (it == index.end()) {
      sink.add(line, "unknown " + std::string(what) + " id " + std::to_string(other_id));
      continue;
    }
    const Segment& other = model.segments[it->second];
    const auto& back = parents ? other.children : other.parents;
    if (std::find(back.begin(), back.end(), s.id) == back.end()) {
      sink.add(line, "segment " + std::to_string(s.id) + " lists " + std::to_string(other_id) + " as " + what + " but " +
                         std::to_string(other_id) + " does not list " + std::to_string(s.id) + " as " +
                         (parents ? "child" : "parent"));
      continue;
    }
    if (!parents) check_child_gap(s, other, line, sink);
  }
}

}  // namespace

void validate_semantics(const VesselModel& model, const std::vector<SegmentLines>& lines, ErrorSink& sink) {
  const auto line_of = [&](std::size_t i, int SegmentLines::*field) {
    return i < lines.size() ? lines[i].*field : 0;
  };
  std::unordered_map<std::int32_t, std::size_t> index;
  for (std::size_t i = 0; i < model.segments.size(); ++i) {
    const Segment& s = model.segments[i];
    if (!index.emplace(s.id, i).second) {
      sink.add(line_of(i, &SegmentLines::g), "duplicate segment id " + std::to_string(s.id));
    }
    check_segment_fields(s, line_of(i, &SegmentLines::g), line_of(i, &SegmentLines::n), sink);
  }
  for (std::size_t i = 0; i < model.segments.size() && !sink.full(); ++i) {
    check_links(model, index, model.segments[i], true, line_of(i, &SegmentLines::p), sink);
    check_links(model, index, model.segments[i], false, line_of(i, &SegmentLines::c), sink);
  }
}

}  // namespace detail

std::vector<Diagnostic> validate_model(const VesselModel& model, std::string_view file_name) {
  std::vector<Diagnostic> errors;
  detail::ErrorSink sink(file_name, errors);
  detail::validate_semantics(model, {}, sink);
  return errors;
}

}  // namespace cathbox::vessel
