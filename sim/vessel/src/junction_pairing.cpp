#include "junction_pairing.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <unordered_map>
#include <utility>

#include <glm/geometric.hpp>

namespace cathbox::vessel::detail {
namespace {

using Triangle = std::array<int, 3>;

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
      for (int e = 0; e < 3; ++e) edge_tri.emplace_back(directed_edge_key(tris[t][e], tris[t][(e + 1) % 3]), static_cast<int>(t));
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
        const auto it = std::upper_bound(edge_tri.begin(), edge_tri.end(), std::pair{directed_edge_key(b, a), 0}, by_edge);
        if (it == edge_tri.begin() || std::prev(it)->first != directed_edge_key(b, a)) continue;
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

}  // namespace

std::vector<std::vector<int>> pair_into_quads(const std::vector<Triangle>& tris, const std::vector<glm::dvec3>& points,
                                              int ring_points) {
  return Pairing(tris, points, ring_points).run();
}

}  // namespace cathbox::vessel::detail
