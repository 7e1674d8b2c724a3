#include "vessel_import/swc_reader.hpp"

#include <charconv>
#include <cmath>
#include <string>
#include <unordered_map>

#include "base/result.hpp"
#include "base/text_tokens.hpp"

namespace cathbox::vessel_import {
namespace {

constexpr std::size_t kMaxErrors = 100;

using SampleIndex = std::unordered_map<std::int64_t, std::size_t>;  // id -> sample

void add_error(SwcRead& out, std::string_view file, int line, std::string message) {
  if (out.errors.size() < kMaxErrors) out.errors.push_back({std::string(file), line, 0, std::move(message)});
}

// One sample line's 7 columns (id type x y z radius parent), or what is wrong with them.
base::Result<SwcSample> parse_sample(const std::vector<std::string_view>& tokens, int line_no) {
  if (tokens.size() != 7) return base::Error{"expected 7 columns (id type x y z radius parent), got " + std::to_string(tokens.size())};
  SwcSample s;
  s.line = line_no;
  const auto id = base::text::parse_integer(tokens[0]);
  const auto type = base::text::parse_integer(tokens[1]);
  const auto parent = base::text::parse_integer(tokens[6]);
  if (!id || *id < 0) return base::Error{"sample id " + base::text::quoted(tokens[0]) + " is not a non-negative integer"};
  if (!type) return base::Error{"type " + base::text::quoted(tokens[1]) + " is not an integer"};
  if (!parent || *parent < -1) return base::Error{"parent " + base::text::quoted(tokens[6]) + " is not a sample id or -1"};
  double values[4];
  static constexpr const char* kNames[4] = {"x", "y", "z", "radius"};
  for (int k = 0; k < 4; ++k) {
    const auto v = base::text::parse_double(tokens[static_cast<std::size_t>(k) + 2]);
    if (!v || !std::isfinite(*v)) {
      return base::Error{std::string(kNames[k]) + " " + base::text::quoted(tokens[static_cast<std::size_t>(k) + 2]) +
                         " is not a finite number"};
    }
    values[k] = *v;
  }
  s.id = *id;
  s.type = *type;
  s.parent = *parent;
  s.pos = {values[0], values[1], values[2]};
  s.radius = values[3];
  if (s.parent == s.id) return base::Error{"sample " + std::to_string(s.id) + " is its own parent"};
  return s;
}

// The samples line by line (comments after '#', blank lines skipped), ids unique.
void read_samples(std::string_view text, std::string_view file, SwcRead& out, SampleIndex& index) {
  int line_no = 0;
  for (std::size_t pos = 0; pos <= text.size() && out.errors.size() < kMaxErrors;) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    const std::vector<std::string_view> tokens = base::text::split_tokens(line);
    if (tokens.empty()) continue;
    base::Result<SwcSample> s = parse_sample(tokens, line_no);
    if (!s) {
      add_error(out, file, line_no, s.error().message);
      continue;
    }
    const auto [it, inserted] = index.emplace(s->id, out.samples.size());
    if (!inserted) {
      add_error(out, file, line_no, "sample id " + std::to_string(s->id) + " already used on line " +
                                        std::to_string(out.samples[it->second].line));
      continue;
    }
    out.samples.push_back(*s);
  }
}

// Parent links must lead to a root: walk up from every sample, marking what is known to.
void check_no_loops(std::string_view file, const SampleIndex& index, SwcRead& out) {
  std::vector<char> state(out.samples.size(), 0);  // 0 unknown, 1 on the current walk, 2 reaches a root
  std::vector<std::size_t> walk;
  for (std::size_t start = 0; start < out.samples.size() && out.ok(); ++start) {
    walk.clear();
    std::size_t cur = start;
    while (state[cur] == 0) {
      state[cur] = 1;
      walk.push_back(cur);
      const std::int64_t parent = out.samples[cur].parent;
      if (parent < 0) break;
      cur = index.at(parent);
    }
    if (state[cur] == 1 && out.samples[cur].parent >= 0) {
      add_error(out, file, out.samples[cur].line,
                "sample " + std::to_string(out.samples[cur].id) + " is its own ancestor (the parent links form a loop)");
    }
    for (std::size_t i : walk) state[i] = 2;
  }
}

}  // namespace

SwcRead parse_swc(std::string_view text, std::string_view file) {
  SwcRead out;
  SampleIndex index;
  read_samples(text, file, out, index);
  if (!out.ok()) return out;
  if (out.samples.empty()) {
    add_error(out, file, 0, "no samples");
    return out;
  }
  for (const SwcSample& s : out.samples) {
    if (s.parent >= 0 && !index.contains(s.parent)) add_error(out, file, s.line, "parent " + std::to_string(s.parent) + " is not defined");
  }
  if (!out.ok()) return out;
  check_no_loops(file, index, out);
  return out;
}

SwcBranches swc_branches(const std::vector<SwcSample>& samples, double scale_to_mm) {
  SwcBranches out;
  std::unordered_map<std::int64_t, std::size_t> index;
  for (std::size_t i = 0; i < samples.size(); ++i) index.emplace(samples[i].id, i);
  std::vector<std::vector<std::size_t>> children(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (samples[i].parent >= 0) children[index.at(samples[i].parent)].push_back(i);
  }
  const auto is_node = [&](std::size_t i) { return samples[i].parent < 0 || children[i].size() != 1; };
  const auto point = [&](std::size_t i) {
    return vessel::CenterlinePoint{samples[i].pos * scale_to_mm, samples[i].radius * scale_to_mm};
  };
  for (std::size_t n = 0; n < samples.size(); ++n) {
    if (!is_node(n)) continue;
    if (samples[n].parent < 0 && children[n].empty()) ++out.lone_samples;
    for (std::size_t c : children[n]) {
      Branch branch;
      branch.from = static_cast<std::size_t>(samples[n].id);
      // The branch starts at the branching sample, with its own first sample's radius (the
      // branching sample's is the parent's).
      branch.line.points.push_back({point(n).pos_mm, samples[n].parent < 0 ? point(n).radius_mm : point(c).radius_mm});
      std::size_t cur = c;
      for (;;) {
        branch.line.points.push_back(point(cur));
        if (is_node(cur)) break;
        cur = children[cur].front();
      }
      branch.to = static_cast<std::size_t>(samples[cur].id);
      branch.line.name = "swc type " + std::to_string(samples[c].type);
      branch.line.where = "samples " + std::to_string(samples[n].id) + ".." + std::to_string(samples[cur].id);
      out.branches.push_back(std::move(branch));
    }
  }
  return out;
}

}  // namespace cathbox::vessel_import
