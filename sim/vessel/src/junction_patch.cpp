#include "junction_patch.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <unordered_map>
#include <utility>

#include <glm/geometric.hpp>

#include "convex_hull.hpp"

namespace cathbox::vessel::detail {
namespace {

using Triangle = std::array<int, 3>;

[[nodiscard]] std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// Neighbour of a triangle across one of its edges that joins two different rings.
struct Neighbor {
  int tri = -1;
  int a = 0;  // the shared edge as this triangle runs it: a -> b
  int b = 0;
  double length = 0.0;
};

// A chain of band triangles (two neighbours each) between two triple triangles (three
// neighbours each, one point on each of three rings).
struct Path {
  int u = -1;
  int v = -1;
  std::vector<int> inner;
};

// Quad from two triangles sharing an edge (a->b in t1, b->a in t2).
[[nodiscard]] std::vector<int> merge(const Triangle& t1, const Triangle& t2) {
  for (int e = 0; e < 3; ++e) {
    const int a = t1[e];
    const int b = t1[(e + 1) % 3];
    const int c = t1[(e + 2) % 3];
    for (int f = 0; f < 3; ++f) {
      if (t2[f] == b && t2[(f + 1) % 3] == a) return {a, t2[(f + 2) % 3], b, c};
    }
  }
  return {t1[0], t1[1], t1[2]};  // not adjacent: never happens for matched pairs
}

class Pairing {
 public:
  Pairing(const std::vector<Triangle>& tris, const std::vector<glm::dvec3>& points, int ring_points)
      : tris_(tris), partner_(tris.size(), -1), nbs_(tris.size()) {
    // Directed edge -> triangle, sorted by edge (ties keep insertion order: the last one wins).
    std::vector<std::pair<std::uint64_t, int>> edge_tri;
    edge_tri.reserve(3 * tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) {
      for (int e = 0; e < 3; ++e) edge_tri.emplace_back(edge_key(tris[t][e], tris[t][(e + 1) % 3]), static_cast<int>(t));
    }
    const auto by_edge = [](const std::pair<std::uint64_t, int>& x, const std::pair<std::uint64_t, int>& y) {
      return x.first < y.first;
    };
    std::stable_sort(edge_tri.begin(), edge_tri.end(), by_edge);
    for (std::size_t t = 0; t < tris.size(); ++t) {
      for (int e = 0; e < 3; ++e) {
        const int a = tris[t][e];
        const int b = tris[t][(e + 1) % 3];
        if (a / ring_points == b / ring_points) continue;
        const auto it = std::upper_bound(edge_tri.begin(), edge_tri.end(), std::pair{edge_key(b, a), 0}, by_edge);
        if (it == edge_tri.begin() || std::prev(it)->first != edge_key(b, a)) continue;
        nbs_[t].push_back({std::prev(it)->second, a, b, glm::length(points[static_cast<std::size_t>(a)] -
                                                        points[static_cast<std::size_t>(b)])});
      }
    }
  }

  std::vector<std::vector<int>> run() {
    bool structured = true;
    std::vector<int> triples;
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      if (nbs_[t].size() == 3) triples.push_back(static_cast<int>(t));
      else if (nbs_[t].size() != 2) structured = false;
    }
    if (structured && triples.size() <= 10) {
      match_structured(triples);
    }
    greedy();
    std::vector<std::vector<int>> faces;
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      const int p = partner_[t];
      if (p < 0) faces.push_back({tris_[t][0], tris_[t][1], tris_[t][2]});
      else if (p > static_cast<int>(t)) faces.push_back(merge(tris_[t], tris_[static_cast<std::size_t>(p)]));
    }
    return faces;
  }

 private:
  [[nodiscard]] double link(int t1, int t2) const {
    for (const Neighbor& n : nbs_[static_cast<std::size_t>(t1)]) {
      if (n.tri == t2) return n.length;
    }
    return 0.0;
  }
  // Pairs two triangles if they are neighbours and both still free (guards every caller).
  void pair(int a, int b) {
    const auto& na = nbs_[static_cast<std::size_t>(a)];
    const bool adjacent = std::any_of(na.begin(), na.end(), [b](const Neighbor& n) { return n.tri == b; });
    if (a == b || !adjacent || partner_[static_cast<std::size_t>(a)] >= 0 || partner_[static_cast<std::size_t>(b)] >= 0) {
      return;
    }
    partner_[static_cast<std::size_t>(a)] = b;
    partner_[static_cast<std::size_t>(b)] = a;
  }

  // Exact perfect matching on the "cubic graph with subdivided edges" structure: each triple
  // triangle picks the chain it pairs into; chains must then have an even remainder.
  void match_structured(const std::vector<int>& triples) {
    Chains chains;
    if (!trace_chains(triples, chains)) return;
    const std::vector<int> best_choice = best_chain_choice(triples.size(), chains);
    if (best_choice.empty()) return;
    std::vector<std::array<char, 2>> used(chains.paths.size());
    (void)mark_chain_ends(best_choice, chains, used);
    for (std::size_t p = 0; p < chains.paths.size(); ++p) pair_along(chains.paths[p], used[p]);
    match_cycles();
  }

  // The chains between triple triangles, and for every triple's three neighbour slots the chain
  // it leads into (path index, end 0 at u / 1 at v; -1 when it leads into a chain traced from the
  // other side).
  struct Chains {
    std::vector<Path> paths;
    std::vector<std::array<std::pair<int, int>, 3>> slot_path;
  };

  // Follows every slot of every triple along its band triangles to the next triple. False when a
  // chain ends on a triangle that is not a triple (no structure to match).
  [[nodiscard]] bool trace_chains(const std::vector<int>& triples, Chains& chains) const {
    chains.slot_path.resize(triples.size());
    for (auto& slots : chains.slot_path) slots.fill({-1, -1});
    std::unordered_map<int, int> triple_index;
    for (std::size_t i = 0; i < triples.size(); ++i) triple_index[triples[i]] = static_cast<int>(i);
    std::vector<char> claimed(tris_.size(), 0);
    for (std::size_t i = 0; i < triples.size(); ++i) {
      const int u = triples[i];
      for (int s = 0; s < 3; ++s) {
        const Neighbor& first = nbs_[static_cast<std::size_t>(u)][static_cast<std::size_t>(s)];
        Path path;
        path.u = u;
        int prev_a = first.a;
        int prev_b = first.b;
        int cur = first.tri;
        bool duplicate = false;
        while (nbs_[static_cast<std::size_t>(cur)].size() == 2) {
          if (claimed[static_cast<std::size_t>(cur)]) {
            duplicate = true;
            break;
          }
          claimed[static_cast<std::size_t>(cur)] = 1;
          path.inner.push_back(cur);
          const auto& cn = nbs_[static_cast<std::size_t>(cur)];
          const int exit = (cn[0].a == prev_b && cn[0].b == prev_a) ? 1 : 0;
          prev_a = cn[static_cast<std::size_t>(exit)].a;
          prev_b = cn[static_cast<std::size_t>(exit)].b;
          cur = cn[static_cast<std::size_t>(exit)].tri;
        }
        if (duplicate) continue;
        if (path.inner.empty() && cur < u) continue;  // direct triple-triple link seen from the other side
        path.v = cur;
        const int index = static_cast<int>(chains.paths.size());
        chains.slot_path[i][static_cast<std::size_t>(s)] = {index, 0};
        // The v side: find v's slot that leads back (the edge we arrived through).
        const auto vi = triple_index.find(cur);
        if (vi == triple_index.end()) return false;
        const auto& vn = nbs_[static_cast<std::size_t>(cur)];
        for (int vs = 0; vs < 3; ++vs) {
          if (vn[static_cast<std::size_t>(vs)].a == prev_b && vn[static_cast<std::size_t>(vs)].b == prev_a) {
            chains.slot_path[static_cast<std::size_t>(vi->second)][static_cast<std::size_t>(vs)] = {index, 1};
          }
        }
        chains.paths.push_back(std::move(path));
      }
    }
    return true;
  }

  // Marks the chain ends the triples' choices pair into; false when a choice leads nowhere.
  [[nodiscard]] static bool mark_chain_ends(const std::vector<int>& choice, const Chains& chains,
                                            std::vector<std::array<char, 2>>& used) {
    for (auto& u : used) u = {0, 0};
    for (std::size_t i = 0; i < choice.size(); ++i) {
      const auto [p, end] = chains.slot_path[i][static_cast<std::size_t>(choice[i])];
      if (p < 0) return false;
      used[static_cast<std::size_t>(p)][static_cast<std::size_t>(end)] = 1;
    }
    return true;
  }

  // The removed edges' total length when every chain is paired with the given ends taken, or
  // -1 when a chain cannot be (more ends than triangles, or an odd remainder).
  [[nodiscard]] double chain_score(const Chains& chains, const std::vector<std::array<char, 2>>& used) const {
    double score = 0.0;
    for (std::size_t p = 0; p < chains.paths.size(); ++p) {
      const Path& path = chains.paths[p];
      const int n = static_cast<int>(path.inner.size());
      const int front = used[p][0];
      const int back = used[p][1];
      if (n == 0) {
        if (front != back) return -1.0;
        if (front) score += link(path.u, path.v);
        continue;
      }
      if (front + back > n || (n - front - back) % 2 != 0) return -1.0;
      if (front) score += link(path.u, path.inner.front());
      if (back) score += link(path.inner.back(), path.v);
      for (int k = front; k + 1 <= n - 1 - back; k += 2) {
        score += link(path.inner[static_cast<std::size_t>(k)], path.inner[static_cast<std::size_t>(k + 1)]);
      }
    }
    return score;
  }

  // Enumerates the triples' choices (3^triples) and keeps the first feasible one of the highest
  // score; empty when none is feasible.
  [[nodiscard]] std::vector<int> best_chain_choice(std::size_t triples, const Chains& chains) const {
    std::size_t combos = 1;
    for (std::size_t i = 0; i < triples; ++i) combos *= 3;
    double best_score = -1.0;
    std::vector<int> best_choice;
    std::vector<int> choice(triples, 0);
    std::vector<std::array<char, 2>> used(chains.paths.size());
    for (std::size_t combo = 0; combo < combos; ++combo) {
      std::size_t rest = combo;
      for (std::size_t i = 0; i < triples; ++i) {
        choice[i] = static_cast<int>(rest % 3);
        rest /= 3;
      }
      if (!mark_chain_ends(choice, chains, used)) continue;
      const double score = chain_score(chains, used);
      if (score >= 0.0 && score > best_score) {
        best_score = score;
        best_choice = choice;
      }
    }
    return best_choice;
  }

  // Pairs a chain's triangles with its chosen ends taken by the triples.
  void pair_along(const Path& path, const std::array<char, 2>& used) {
    const int n = static_cast<int>(path.inner.size());
    const int front = used[0];
    const int back = used[1];
    if (n == 0) {
      if (front) pair(path.u, path.v);
      return;
    }
    if (front) pair(path.u, path.inner.front());
    if (back) pair(path.inner.back(), path.v);
    for (int k = front; k + 1 <= n - 1 - back; k += 2) {
      pair(path.inner[static_cast<std::size_t>(k)], path.inner[static_cast<std::size_t>(k + 1)]);
    }
  }

  // Band triangles on closed chains (two rings only, or chains not touching a triple): pick the
  // alternate pairing with the longer removed edges.
  void match_cycles() {
    for (std::size_t start = 0; start < tris_.size(); ++start) {
      if (partner_[start] >= 0 || nbs_[start].size() != 2) continue;
      std::vector<int> cycle;
      int cur = static_cast<int>(start);
      int prev_a = nbs_[start][1].b;  // pretend we entered through slot 1
      int prev_b = nbs_[start][1].a;
      bool closed = false;
      for (std::size_t guard = 0; guard <= tris_.size(); ++guard) {
        const auto& cn = nbs_[static_cast<std::size_t>(cur)];
        if (cn.size() != 2 || partner_[static_cast<std::size_t>(cur)] >= 0) break;
        cycle.push_back(cur);
        const int exit = (cn[0].a == prev_b && cn[0].b == prev_a) ? 1 : 0;
        prev_a = cn[static_cast<std::size_t>(exit)].a;
        prev_b = cn[static_cast<std::size_t>(exit)].b;
        cur = cn[static_cast<std::size_t>(exit)].tri;
        if (cur == static_cast<int>(start)) {
          closed = true;
          break;
        }
      }
      if (!closed || cycle.size() % 2 != 0) continue;
      const std::size_t n = cycle.size();
      double score[2] = {0.0, 0.0};
      for (std::size_t parity = 0; parity < 2; ++parity) {
        for (std::size_t k = parity; k < n + parity; k += 2) score[parity] += link(cycle[k % n], cycle[(k + 1) % n]);
      }
      const std::size_t parity = score[1] > score[0] ? 1 : 0;
      for (std::size_t k = parity; k < n + parity; k += 2) pair(cycle[k % n], cycle[(k + 1) % n]);
    }
  }

  void greedy() {
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      if (partner_[t] >= 0) continue;
      int best = -1;
      double best_len = -1.0;
      for (const Neighbor& n : nbs_[t]) {
        if (partner_[static_cast<std::size_t>(n.tri)] < 0 && n.length > best_len) {
          best = n.tri;
          best_len = n.length;
        }
      }
      if (best >= 0) pair(static_cast<int>(t), best);
    }
  }

  const std::vector<Triangle>& tris_;
  std::vector<int> partner_;
  std::vector<std::vector<Neighbor>> nbs_;
};

// The patch from the hull of `hull_points` (the rings, or their images on the sphere), paired into
// quads by the lengths of the real `points`' edges.
JunctionPatchResult hull_patch(const std::vector<glm::dvec3>& hull_points, const std::vector<glm::dvec3>& points,
                               const std::vector<JunctionRing>& rings, int ring_points) {
  JunctionPatchResult result;
  const int m_count = ring_points;
  const auto ring_of = [m_count](int v) { return v / m_count; };
  const std::vector<Triangle> hull = convex_hull(hull_points);
  if (hull.empty()) {
    result.error = "its rings span no volume";
    return result;
  }
  std::vector<Triangle> patch;
  for (const Triangle& t : hull) {
    if (ring_of(t[0]) == ring_of(t[1]) && ring_of(t[1]) == ring_of(t[2])) continue;  // a ring's own disc
    patch.push_back(t);
  }
  // The patch must be bounded by exactly the ring edges, each once, in the direction opposite
  // to the tube's use; every other edge must be shared by two patch triangles.
  std::unordered_map<std::uint64_t, int> edges;
  for (const Triangle& t : patch) {
    for (int e = 0; e < 3; ++e) ++edges[edge_key(t[e], t[(e + 1) % 3])];
  }
  std::size_t ring_edges = 0;
  for (const auto& [key, count] : edges) {
    const int a = static_cast<int>(key >> 32);
    const int b = static_cast<int>(key & 0xffffffffu);
    if (count != 1) {
      result.error = "its hull is not manifold";
      return result;
    }
    if (ring_of(a) == ring_of(b)) {
      const int r = ring_of(a);
      const int ma = a % m_count;
      const int mb = b % m_count;
      const bool forward = mb == (ma + 1) % m_count;
      const bool backward = ma == (mb + 1) % m_count;
      const bool tube_forward = rings[static_cast<std::size_t>(r)].tube_runs_forward;
      if (!(tube_forward ? backward : forward)) {
        result.error = "branches overlap (a ring is not on the junction's hull)";
        return result;
      }
      ++ring_edges;
    } else if (edges.count(edge_key(b, a)) == 0) {
      result.error = "its hull is open";
      return result;
    }
  }
  if (ring_edges != rings.size() * static_cast<std::size_t>(m_count)) {
    result.error = "branches overlap (a ring is not on the junction's hull)";
    return result;
  }
  result.faces = Pairing(patch, points, ring_points).run();
  return result;
}

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinDirectionAngle = 10.0 * kPi / 180.0;  // directions closer than this are pushed apart
constexpr double kDirectionStep = 0.05;                    // radians per push
constexpr int kDirectionIterations = 400;
constexpr double kCapShare = 0.4;   // a ring's circle: this share of the angle to the nearest other direction
constexpr double kMaxCapAngle = 1.0;  // radians

// A unit vector perpendicular to u leaning towards `towards` (any perpendicular when it is along u).
glm::dvec3 perpendicular_towards(const glm::dvec3& u, const glm::dvec3& towards) {
  glm::dvec3 side = towards - glm::dot(towards, u) * u;
  if (glm::length(side) < 1e-9) {
    side = std::abs(u.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    side -= glm::dot(side, u) * u;
  }
  return glm::normalize(side);
}

// The rings' leaving directions, pairs closer than kMinDirectionAngle pushed apart along the
// great circle through them (their ring centres' offset decides the side when they coincide).
std::vector<glm::dvec3> separated_directions(const std::vector<JunctionRingFrame>& frames) {
  std::vector<glm::dvec3> u;
  for (const JunctionRingFrame& f : frames) u.push_back(glm::normalize(f.out));
  const double close = std::cos(kMinDirectionAngle);
  for (int iteration = 0; iteration < kDirectionIterations; ++iteration) {
    bool moved = false;
    for (std::size_t i = 0; i < u.size(); ++i) {
      for (std::size_t j = i + 1; j < u.size(); ++j) {
        if (glm::dot(u[i], u[j]) < close) continue;
        const glm::dvec3 apart = u[i] - u[j];
        const glm::dvec3 hint = glm::length(apart) > 1e-9 ? apart : frames[i].center - frames[j].center;
        const glm::dvec3 side_i = perpendicular_towards(u[i], hint);
        const glm::dvec3 side_j = perpendicular_towards(u[j], -hint);
        u[i] = glm::normalize(u[i] + kDirectionStep * side_i);
        u[j] = glm::normalize(u[j] + kDirectionStep * side_j);
        moved = true;
      }
    }
    if (!moved) break;
  }
  return u;
}

}  // namespace

JunctionPatchResult build_junction_patch(const std::vector<glm::dvec3>& points, const std::vector<JunctionRing>& rings,
                                         int ring_points) {
  return hull_patch(points, points, rings, ring_points);
}

JunctionPatchResult build_spherical_junction_patch(const std::vector<glm::dvec3>& points,
                                                   const std::vector<JunctionRing>& rings,
                                                   const std::vector<JunctionRingFrame>& frames, int ring_points) {
  const std::vector<glm::dvec3> u = separated_directions(frames);
  std::vector<glm::dvec3> sphere;
  sphere.reserve(points.size());
  for (std::size_t i = 0; i < u.size(); ++i) {
    double nearest = kPi;
    for (std::size_t j = 0; j < u.size(); ++j) {
      if (j != i) nearest = std::min(nearest, std::acos(std::clamp(glm::dot(u[i], u[j]), -1.0, 1.0)));
    }
    const double cap = std::min(kCapShare * nearest, kMaxCapAngle);
    // The ring's own frame turned to be perpendicular to u, keeping its sense of rotation about
    // the leaving direction (the hull's face for the ring must run its edges as the tube does).
    const glm::dvec3 normal = perpendicular_towards(u[i], frames[i].normal);
    const double sense = glm::dot(glm::cross(frames[i].normal, frames[i].binormal), frames[i].out) < 0.0 ? -1.0 : 1.0;
    const glm::dvec3 binormal = sense * glm::cross(u[i], normal);
    for (int m = 0; m < ring_points; ++m) {
      const double angle = 2.0 * kPi * m / ring_points;
      sphere.push_back(std::cos(cap) * u[i] + std::sin(cap) * (std::cos(angle) * normal + std::sin(angle) * binormal));
    }
  }
  return hull_patch(sphere, points, rings, ring_points);
}

}  // namespace cathbox::vessel::detail
