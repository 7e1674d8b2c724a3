// The HCLM reader: the thesis' central axis model file (Appendix A) parsed line by line into a
// VesselModel, each error located; the model checks are in hclm_checks.cpp, the writer in
// hclm_write.cpp.
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

#include "hclm_checks.hpp"

namespace cathbox::vessel {
namespace {

using base::text::parse_double;
using base::text::parse_integer;
using base::text::quoted;
using base::text::split_tokens;
using base::text::trim;
using detail::ErrorSink;
using detail::SegmentLines;
using detail::validate_semantics;

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

}  // namespace cathbox::vessel
