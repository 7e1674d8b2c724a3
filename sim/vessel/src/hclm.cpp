#include "vessel/hclm.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "base/float_chars.hpp"
#include "base/text_tokens.hpp"
#include "vessel/point_range.hpp"

namespace cathbox::vessel {
namespace {

using base::text::parse_double;
using base::text::parse_integer;
using base::text::quoted;
using base::text::split_tokens;
using base::text::trim;

constexpr std::size_t kMaxErrors = 100;

// Source lines of one segment block, for diagnostics of cross-segment rules.
struct SegmentLines {
  int g = 0;
  int p = 0;
  int c = 0;
  int n = 0;
};

class ErrorSink {
 public:
  ErrorSink(std::string_view file, std::vector<Diagnostic>& out) : file_(file), out_(out) {}
  void add(int line, std::string message) {
    if (out_.size() < kMaxErrors) out_.push_back({std::string(file_), line, std::move(message)});
  }
  [[nodiscard]] bool full() const { return out_.size() >= kMaxErrors; }

 private:
  std::string_view file_;
  std::vector<Diagnostic>& out_;
};

std::string format_double(double value) {
  char buf[64];
  const auto [ptr, ec] = base::double_chars(buf, buf + sizeof buf, value);
  if (ec != std::errc()) return "nan";
  return std::string(buf, ptr);
}

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

// Cross-segment rules shared by the reader and validate_model(). `lines` may be empty.
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

class Reader {
 public:
  Reader(std::string_view text, std::string_view file) : text_(text), sink_(file, result_.errors) {}

  HclmReadResult run() {
    std::size_t pos = 0;
    int line_no = 0;
    while (pos <= text_.size() && !sink_.full()) {
      std::size_t end = text_.find('\n', pos);
      if (end == std::string_view::npos) end = text_.size();
      ++line_no;
      handle_line(text_.substr(pos, end - pos), line_no);
      pos = end + 1;
    }
    finish_segment();
    if (!seen_s_) {
      sink_.add(1, "missing 's' line (segment count)");
    } else if (declared_segments_ >= 0 &&
               declared_segments_ != static_cast<std::int64_t>(result_.model.segments.size())) {
      sink_.add(s_line_, "'s " + std::to_string(declared_segments_) + "' but the file has " +
                             std::to_string(result_.model.segments.size()) + " segments");
    }
    if (result_.errors.empty()) validate_semantics(result_.model, lines_, sink_);
    return std::move(result_);
  }

 private:
  void handle_line(std::string_view raw, int line) {
    const std::string_view content = trim(raw);
    if (content.empty()) return;
    const std::vector<std::string_view> tokens = split_tokens(content);
    const std::string_view label = tokens.front();
    if (label.size() != 1 || std::string_view("sglfpcnv").find(label[0]) == std::string_view::npos) {
      sink_.add(line, "unknown label " + quoted(label));
      return;
    }
    const char kind = label[0];
    if (kind == 's') {
      handle_s(tokens, line);
      return;
    }
    if (!seen_s_) {
      sink_.add(line, "expected the 's' line (segment count) first");
      seen_s_ = true;  // report once
      declared_segments_ = -1;
    }
    if (kind == 'g') {
      handle_g(tokens, line);
      return;
    }
    if (!in_segment_) {
      sink_.add(line, "'" + std::string(label) + "' line outside a segment (no 'g' line before it)");
      return;
    }
    Segment& seg = result_.model.segments.back();
    switch (kind) {
      case 'l': {
        if (seen_l_) sink_.add(line, "second 'l' line in segment " + std::to_string(seg.id));
        seen_l_ = true;
        seg.name = std::string(trim(content.substr(1)));
        return;
      }
      case 'f': {
        if (seen_f_) sink_.add(line, "second 'f' line in segment " + std::to_string(seg.id));
        seen_f_ = true;
        if (tokens.size() != 2) {
          sink_.add(line, "'f' takes one number (the flow)");
          return;
        }
        const auto flow = number(tokens[1], line, "flow");
        if (flow) seg.flow = *flow;
        return;
      }
      case 'p':
      case 'c':
        handle_list(tokens, line, kind == 'p' ? seg.parents : seg.children, kind);
        return;
      case 'n':
        handle_n(tokens, line);
        return;
      case 'v':
        handle_v(tokens, line);
        return;
      default:
        return;
    }
  }

  void handle_s(const std::vector<std::string_view>& tokens, int line) {
    if (seen_s_) {
      sink_.add(line, "second 's' line");
      return;
    }
    if (in_segment_ || !result_.model.segments.empty()) sink_.add(line, "'s' line must come before the segments");
    seen_s_ = true;
    s_line_ = line;
    declared_segments_ = single_count(tokens, line, "'s' takes one count (the number of segments)", "segment count");
  }

  void handle_g(const std::vector<std::string_view>& tokens, int line) {
    finish_segment();
    in_segment_ = true;
    seen_l_ = seen_f_ = seen_p_ = seen_c_ = seen_n_ = false;
    declared_points_ = 0;
    v_lines_ = 0;
    Segment seg;
    if (tokens.size() != 2) {
      sink_.add(line, "'g' takes one segment id");
    } else if (const auto id = parse_integer(tokens[1]);
               !id || *id < std::numeric_limits<std::int32_t>::min() || *id > std::numeric_limits<std::int32_t>::max()) {
      sink_.add(line, "segment id " + quoted(tokens[1]) + " is not a 32-bit integer");
    } else {
      seg.id = static_cast<std::int32_t>(*id);
    }
    result_.model.segments.push_back(std::move(seg));
    lines_.push_back(SegmentLines{line, 0, 0, 0});
  }

  void handle_list(const std::vector<std::string_view>& tokens, int line, std::vector<std::int32_t>& out, char kind) {
    bool& seen = kind == 'p' ? seen_p_ : seen_c_;
    const char* what = kind == 'p' ? "parent" : "child";
    if (seen) sink_.add(line, std::string("second '") + kind + "' line in segment " +
                                  std::to_string(result_.model.segments.back().id));
    seen = true;
    (kind == 'p' ? lines_.back().p : lines_.back().c) = line;
    if (tokens.size() < 2) {
      sink_.add(line, std::string("'") + kind + "' takes a count and that many " + what + " ids");
      return;
    }
    const auto count = count_value(tokens[1], line, std::string(what) + " count");
    if (!count) return;
    const std::size_t listed = tokens.size() - 2;
    if (static_cast<std::uint64_t>(*count) != listed) {
      sink_.add(line, std::string(what) + " count " + std::to_string(*count) + " but " + std::to_string(listed) +
                          " ids listed");
      return;
    }
    out.clear();
    for (std::size_t i = 2; i < tokens.size(); ++i) {
      const auto id = parse_integer(tokens[i]);
      if (!id || *id < std::numeric_limits<std::int32_t>::min() || *id > std::numeric_limits<std::int32_t>::max()) {
        sink_.add(line, std::string(what) + " id " + quoted(tokens[i]) + " is not a 32-bit integer");
        return;
      }
      out.push_back(static_cast<std::int32_t>(*id));
    }
  }

  void handle_n(const std::vector<std::string_view>& tokens, int line) {
    if (seen_n_) {
      sink_.add(line, "second 'n' line in segment " + std::to_string(result_.model.segments.back().id));
      return;
    }
    seen_n_ = true;
    lines_.back().n = line;
    declared_points_ = single_count(tokens, line, "'n' takes one count (the number of 'v' lines)", "point count");
    // Reserve only what the remaining text could hold (a 'v' line needs at least 9 bytes).
    if (declared_points_ > 0) {
      const auto plausible = static_cast<std::int64_t>(text_.size() / 9 + 1);
      result_.model.segments.back().points.reserve(static_cast<std::size_t>(std::min(declared_points_, plausible)));
    }
  }

  void handle_v(const std::vector<std::string_view>& tokens, int line) {
    ++v_lines_;
    if (!seen_n_) {
      if (v_lines_ == 1) sink_.add(line, "'v' line before the 'n' line of its segment");
      return;
    }
    if (declared_points_ >= 0 && v_lines_ > declared_points_) {
      if (v_lines_ == declared_points_ + 1) {
        sink_.add(line, "more 'v' lines than 'n " + std::to_string(declared_points_) + "' declares");
      }
      return;
    }
    if (tokens.size() != 5) {
      sink_.add(line, "'v' takes 4 numbers (x y z radius), got " + std::to_string(tokens.size() - 1));
      return;
    }
    CenterlinePoint p;
    const auto x = number(tokens[1], line, "x");
    const auto y = number(tokens[2], line, "y");
    const auto z = number(tokens[3], line, "z");
    const auto r = number(tokens[4], line, "radius");
    if (!x || !y || !z || !r) return;
    if (!(*r > 0.0)) {
      sink_.add(line, "radius " + quoted(tokens[4]) + " must be > 0");
      return;
    }
    p.pos_mm = glm::dvec3(*x, *y, *z);
    p.radius_mm = *r;
    if (std::string problem = point_range_problem(p.pos_mm, p.radius_mm); !problem.empty()) {
      sink_.add(line, problem);
      return;
    }
    result_.model.segments.back().points.push_back(p);
  }

  void finish_segment() {
    if (!in_segment_) return;
    in_segment_ = false;
    const Segment& seg = result_.model.segments.back();
    const SegmentLines& lines = lines_.back();
    const std::string id = std::to_string(seg.id);
    if (!seen_p_) sink_.add(lines.g, "segment " + id + " has no 'p' line");
    if (!seen_c_) sink_.add(lines.g, "segment " + id + " has no 'c' line");
    if (!seen_n_) {
      sink_.add(lines.g, "segment " + id + " has no 'n' line");
      return;
    }
    if (declared_points_ >= 0 && v_lines_ < declared_points_) {
      sink_.add(lines.n, "'n " + std::to_string(declared_points_) + "' but only " + std::to_string(v_lines_) +
                             " 'v' lines follow");
    }
  }

  std::optional<double> number(std::string_view token, int line, const char* what) {
    const auto value = parse_double(token);
    if (!value) {
      sink_.add(line, std::string(what) + " " + quoted(token) + " is not a number");
      return std::nullopt;
    }
    if (!std::isfinite(*value)) {
      sink_.add(line, std::string(what) + " " + quoted(token) + " is not finite");
      return std::nullopt;
    }
    return value;
  }

  // The count of a line that holds exactly one ("s N", "n N"); -1 after reporting a problem.
  std::int64_t single_count(const std::vector<std::string_view>& tokens, int line, const char* usage,
                            const char* what) {
    if (tokens.size() != 2) {
      sink_.add(line, usage);
      return -1;
    }
    return count_value(tokens[1], line, what).value_or(-1);
  }

  std::optional<std::int64_t> count_value(std::string_view token, int line, const std::string& what) {
    const auto value = parse_integer(token);
    if (!value || *value < 0 || *value > std::numeric_limits<std::int32_t>::max()) {
      sink_.add(line, what + " " + quoted(token) + " is not a count (0 .. 2^31-1)");
      return std::nullopt;
    }
    return value;
  }

  std::string_view text_;
  HclmReadResult result_;
  ErrorSink sink_;
  std::vector<SegmentLines> lines_;
  bool seen_s_ = false;
  int s_line_ = 0;
  std::int64_t declared_segments_ = -1;
  bool in_segment_ = false;
  bool seen_l_ = false, seen_f_ = false, seen_p_ = false, seen_c_ = false, seen_n_ = false;
  std::int64_t declared_points_ = 0;
  std::int64_t v_lines_ = 0;
};

}  // namespace

HclmReadResult read_hclm(std::string_view text, std::string_view file_name) {
  return Reader(text, file_name).run();
}

HclmReadResult load_hclm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    HclmReadResult result;
    result.errors.push_back({path, 0, "cannot open file"});
    return result;
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return read_hclm(buffer.str(), path);
}

std::vector<Diagnostic> validate_model(const VesselModel& model, std::string_view file_name) {
  std::vector<Diagnostic> errors;
  ErrorSink sink(file_name, errors);
  validate_semantics(model, {}, sink);
  return errors;
}

std::string write_hclm(const VesselModel& model) {
  std::string out;
  out.reserve(64 + model.point_count() * 64);
  const auto write_list = [&](char label, const std::vector<std::int32_t>& ids) {
    out += label;
    out += ' ';
    out += std::to_string(ids.size());
    for (std::int32_t id : ids) {
      out += ' ';
      out += std::to_string(id);
    }
    out += '\n';
  };
  out += "s " + std::to_string(model.segments.size()) + "\n";
  for (const Segment& s : model.segments) {
    out += "\ng " + std::to_string(s.id) + "\n";
    out += "l " + s.name + "\n";
    out += "f " + format_double(s.flow) + "\n";
    write_list('p', s.parents);
    write_list('c', s.children);
    out += "n " + std::to_string(s.points.size()) + "\n";
    for (const CenterlinePoint& p : s.points) {
      out += "v " + format_double(p.pos_mm.x) + ' ' + format_double(p.pos_mm.y) + ' ' + format_double(p.pos_mm.z) +
             ' ' + format_double(p.radius_mm) + '\n';
    }
  }
  return out;
}

std::string save_hclm(const VesselModel& model, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return "cannot open " + path + " for writing";
  out << write_hclm(model);
  out.flush();
  if (!out) return "cannot write " + path;
  return {};
}

}  // namespace cathbox::vessel
