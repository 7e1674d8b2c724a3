// The random cases for property tests and benchmarks: trees (CaseGenerator::random_tree) and
// graphs with cycles (CaseGenerator::random_graph), deterministic for a seed.
#include "vessel/case_generator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>

#include "case_network.hpp"
#include "vessel/rotation_minimizing_frame.hpp"

namespace cathbox::vessel {
namespace {

using detail::Knot;
using detail::Network;

// Deterministic uniform numbers (independent of the standard library's distributions).
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0);
  }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }

 private:
  std::mt19937_64 engine_;
};

[[nodiscard]] glm::dvec3 rotate(const glm::dvec3& v, const glm::dvec3& axis, double angle_rad) {
  const glm::dvec3 k = glm::normalize(axis);
  return v * std::cos(angle_rad) + glm::cross(k, v) * std::sin(angle_rad) +
         k * glm::dot(k, v) * (1.0 - std::cos(angle_rad));
}

// A gently curved path of length `length` starting at `start` in direction `dir`.
[[nodiscard]] std::vector<Knot> curved_path(Random& rng, const glm::dvec3& start, const glm::dvec3& dir, double length,
                                            double r0, double r1) {
  const glm::dvec3 side = any_perpendicular(dir);
  const glm::dvec3 bend_axis = rotate(side, dir, rng.uniform(0.0, 2.0 * std::numbers::pi));
  const double bend = rng.uniform(-0.25, 0.25);
  const glm::dvec3 mid_dir = rotate(dir, bend_axis, 0.5 * bend);
  const glm::dvec3 end_dir = rotate(dir, bend_axis, bend);
  const glm::dvec3 mid = start + 0.5 * length * mid_dir;
  return {{start, r0}, {mid, 0.5 * (r0 + r1)}, {mid + 0.5 * length * end_dir, r1}};
}

// random_graph's steps: a ring of junctions joined by ring segments, chords across the ring and
// a side branch per junction; the parent / child relations written once every segment is known.
class RandomGraphBuilder {
 public:
  RandomGraphBuilder(std::uint64_t seed, int cycles) : rng_(seed), cycles_(std::max(cycles, 1)), n_(cycles_ + 2) {
    place_junctions();
  }

  VesselModel build() {
    add_ring();
    add_chords();
    for (int j = 0; j < n_; ++j) add_side_branch(static_cast<std::size_t>(j));
    link_junctions();
    return std::move(staged_);
  }

 private:
  // Each junction collects the ids of segments ending there (ins) and starting there (outs).
  struct Node {
    std::vector<std::int32_t> ins, outs;
  };

  void place_junctions() {
    const double ring_radius = rng_.uniform(22.0, 30.0);
    junction_.resize(static_cast<std::size_t>(n_));
    for (int j = 0; j < n_; ++j) {
      const double a = 2.0 * std::numbers::pi * (j + rng_.uniform(-0.12, 0.12)) / n_;
      junction_[static_cast<std::size_t>(j)] = {ring_radius * std::cos(a), ring_radius * std::sin(a), rng_.uniform(-2.0, 2.0)};
    }
    nodes_.resize(static_cast<std::size_t>(n_));
  }

  double radius() { return rng_.uniform(1.0, 1.6); }

  std::int32_t stage(const std::string& name, const std::vector<Knot>& knots) {
    Network one(1.0);
    one.add(name, knots, {});
    VesselModel m = one.take();
    m.segments[0].id = next_id_++;
    staged_.segments.push_back(m.segments[0]);
    return staged_.segments.back().id;
  }

  // Ring segments, alternating direction so that some junctions are confluences.
  void add_ring() {
    for (int j = 0; j < n_; ++j) {
      const auto a = static_cast<std::size_t>(j);
      const auto b = static_cast<std::size_t>((j + 1) % n_);
      const bool forward = rng_.chance(0.6);
      const glm::dvec3 from = forward ? junction_[a] : junction_[b];
      const glm::dvec3 to = forward ? junction_[b] : junction_[a];
      glm::dvec3 mid = 0.5 * (from + to);
      mid += 0.15 * glm::length(mid) * glm::normalize(glm::dvec3(mid.x, mid.y, 0.0));
      const double r = radius();
      const std::int32_t id = stage("ring", {{from, r}, {mid, r}, {to, r}});
      nodes_[forward ? b : a].ins.push_back(id);
      nodes_[forward ? a : b].outs.push_back(id);
    }
  }

  // Chords from junction 0 to junctions 2..cycles, arching upwards at different heights.
  void add_chords() {
    for (int c = 0; c + 1 < cycles_; ++c) {
      const auto b = static_cast<std::size_t>(2 + c);
      const glm::dvec3 mid = 0.5 * (junction_[0] + junction_[b]) + glm::dvec3(0, 0, 8.0 + 7.0 * c);
      const double r = radius();
      const std::int32_t id = stage("chord", {{junction_[0], r}, {mid, r}, {junction_[b], r}});
      nodes_[0].outs.push_back(id);
      nodes_[b].ins.push_back(id);
    }
  }

  // One outward side branch at junction j (a child, or a parent if nothing starts there); some
  // split again into two free branches (a trifurcation when the junction had 3 ends).
  void add_side_branch(std::size_t j) {
    Node& node = nodes_[j];
    const glm::dvec3 p = junction_[j];
    const glm::dvec3 out = glm::normalize(glm::dvec3(p.x, p.y, 0.0) + glm::dvec3(0, 0, rng_.uniform(-8.0, 8.0)));
    const double r = radius();
    const double length = rng_.uniform(14.0, 22.0);
    if (node.ins.empty()) {
      node.ins.push_back(stage("feeder", {{p + length * out, r}, {p + 0.5 * length * out, r}, {p, r}}));
      return;
    }
    const std::int32_t id = stage("branch", {{p, r}, {p + 0.5 * length * out, r}, {p + length * out, r}});
    node.outs.push_back(id);
    if (!rng_.chance(0.5)) return;
    const glm::dvec3 tip = p + length * out;
    const glm::dvec3 up{0, 0, 1};
    for (double s : {-1.0, 1.0}) {
      const glm::dvec3 dir = glm::normalize(rotate(out, up, s * 0.6));
      const std::int32_t child = stage("twig", {{tip, 0.8 * r}, {tip + 6.0 * dir, 0.8 * r}, {tip + 12.0 * dir, 0.75 * r}});
      Segment& parent = staged_.segments[static_cast<std::size_t>(*staged_.index_of(id))];
      parent.children.push_back(child);
      staged_.segments.back().parents.push_back(id);
    }
  }

  // Every segment into a junction is a parent of every segment out of it.
  void link_junctions() {
    for (const Node& node : nodes_) {
      for (std::int32_t in : node.ins) {
        for (std::int32_t out : node.outs) {
          staged_.segments[static_cast<std::size_t>(*staged_.index_of(in))].children.push_back(out);
          staged_.segments[static_cast<std::size_t>(*staged_.index_of(out))].parents.push_back(in);
        }
      }
    }
  }

  Random rng_;
  int cycles_;
  int n_;  // ring segments
  std::vector<glm::dvec3> junction_;
  std::vector<Node> nodes_;
  VesselModel staged_;
  std::int32_t next_id_ = 1;
};

}  // namespace

VesselModel CaseGenerator::random_tree(std::uint64_t seed, const RandomTreeOptions& options) {
  Random rng(seed);
  Network net(options.spacing_radii);
  struct Tip {
    std::int32_t id;
    glm::dvec3 dir;
    double radius;
  };
  const double r0 = options.root_radius_mm;
  const std::int32_t root = net.add("root", curved_path(rng, {0, 0, 0}, {0, 0, 1}, 10.0 * r0, r0, r0), {});
  std::vector<Tip> queue{{root, {0, 0, 1}, r0}};
  int count = 1;
  const double deg = std::numbers::pi / 180.0;
  for (std::size_t q = 0; q < queue.size() && count < options.segments; ++q) {
    const Tip tip = queue[q];
    int children = rng.chance(options.trifurcation_chance) ? 3 : 2;
    children = std::min(children, options.segments - count);
    const double azimuth0 = rng.uniform(0.0, 2.0 * std::numbers::pi);
    const glm::dvec3 side = any_perpendicular(tip.dir);
    for (int c = 0; c < children; ++c) {
      const double azimuth = azimuth0 + 2.0 * std::numbers::pi * c / std::max(children, 2) + rng.uniform(-0.3, 0.3);
      const double angle = children == 1 ? 0.0
                                         : rng.uniform(options.min_branch_angle_deg, options.max_branch_angle_deg) * deg;
      const glm::dvec3 axis = rotate(side, tip.dir, azimuth);
      const glm::dvec3 dir = glm::normalize(rotate(tip.dir, axis, angle));
      const double r = std::max(0.4, tip.radius * std::pow(1.0 / children, 1.0 / 3.0) * rng.uniform(0.9, 1.05));
      const double length = r * rng.uniform(8.0, 14.0);
      const double r_end = r * rng.uniform(0.9, 1.0);
      const std::int32_t id =
          net.add("branch", curved_path(rng, net.end(tip.id), dir, length, std::min(r, tip.radius), r_end), {tip.id});
      queue.push_back({id, dir, r_end});
      ++count;
    }
  }
  return net.take();
}

VesselModel CaseGenerator::random_graph(std::uint64_t seed, int cycles) { return RandomGraphBuilder(seed, cycles).build(); }

}  // namespace cathbox::vessel
