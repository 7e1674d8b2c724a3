#include "vessel/vessel_graph.hpp"

#include <numeric>
#include <unordered_map>

namespace cathbox::vessel {
namespace {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent_[b] = a;
    return true;
  }

 private:
  std::vector<std::uint32_t> parent_;
};

}  // namespace

VesselGraph::VesselGraph(const VesselModel& model) {
  const std::size_t n = model.segments.size();
  std::unordered_map<std::int32_t, std::uint32_t> index;
  for (std::size_t i = 0; i < n; ++i) index.emplace(model.segments[i].id, static_cast<std::uint32_t>(i));

  // Node of each segment end: ends 2i (start) and 2i+1 (end).
  DisjointSets ends(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::int32_t child : model.segments[i].children) {
      const auto it = index.find(child);
      if (it != index.end()) ends.unite(static_cast<std::uint32_t>(2 * i + 1), 2 * it->second);
    }
    for (std::int32_t parent : model.segments[i].parents) {
      const auto it = index.find(parent);
      if (it != index.end()) ends.unite(2 * it->second + 1, static_cast<std::uint32_t>(2 * i));
    }
  }

  std::unordered_map<std::uint32_t, std::vector<SegmentEnd>> nodes;
  std::vector<std::uint32_t> node_order;
  for (std::uint32_t e = 0; e < 2 * n; ++e) {
    const std::uint32_t root = ends.find(e);
    auto [it, inserted] = nodes.try_emplace(root);
    if (inserted) node_order.push_back(root);
    it->second.push_back(SegmentEnd{e / 2, (e % 2) == 1});
  }

  end_junction_.assign(2 * n, -1);
  for (std::uint32_t root : node_order) {
    const std::vector<SegmentEnd>& node_ends = nodes[root];
    if (node_ends.size() == 1) {
      free_ends_.push_back(node_ends.front());
      continue;
    }
    Junction junction;
    junction.ends = node_ends;
    for (const SegmentEnd& e : node_ends) {
      const Segment& s = model.segments[e.segment];
      if (!s.points.empty()) junction.center_mm += (e.at_end ? s.points.back() : s.points.front()).pos_mm;
      end_junction_[2 * e.segment + (e.at_end ? 1 : 0)] = static_cast<int>(junctions_.size());
    }
    junction.center_mm /= static_cast<double>(node_ends.size());
    junctions_.push_back(std::move(junction));
  }

  // Components and cycles of the graph whose vertices are nodes and whose edges are segments.
  DisjointSets components(2 * n);
  int merges = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (components.unite(ends.find(2 * i), ends.find(2 * i + 1))) ++merges;
  }
  const int node_count = static_cast<int>(node_order.size());
  components_ = node_count - merges;
  cycles_ = static_cast<int>(n) - node_count + components_;
}

}  // namespace cathbox::vessel
