#pragma once
// Contacts between rods, and between the far parts of one rod: the loops of a coil against
// each other, against earlier coils and against the microcatheter's tip. Edges are capsules
// (the segment between two nodes swept by the node radius); two edges closer than the sum of
// their radii plus a margin give each side a contact plane (RodObstacles). Another rod is
// frozen while one is solved, so its side of the gap is the plane; two parts of the same rod
// each take half of the gap. Candidates come from a hash grid of the edges' midpoints, so a
// gather is O(edges). Nothing allocates once the members are set.
#include <cstdint>
#include <span>
#include <vector>

#include "tool/rod.hpp"

namespace cathbox::tool {

class RodContactField final : public RodObstacles {
 public:
  struct Member {
    const Rod* rod = nullptr;
    std::size_t edge_first = 0;   // edges [edge_first, edge_last) take part
    std::size_t edge_last = 0;
    bool self = false;            // contacts of the rod with itself
    // Edges of this member within this depth past the rod's entry do not touch `hollow`: they
    // are still in its lumen (the coil leaving the microcatheter's tip).
    double hollow_depth_mm = 0.0;
    const Rod* hollow = nullptr;
  };

  explicit RodContactField(double margin_mm = 0.05) : margin_(margin_mm) {}

  // The rods taking part in this step (positions are read at each gather).
  void set_members(std::span<const Member> members);
  [[nodiscard]] std::span<const Member> members() const { return members_; }

  void gather(const Rod& rod, std::vector<EdgeContact>& out) const override;
  [[nodiscard]] double margin_mm() const override { return margin_; }

  // Deepest overlap of two non-neighbouring edges (sum of radii minus distance) among the
  // members, and the shortest distance between the centre lines; for tests and metrics.
  struct Overlap {
    double depth_mm = 0.0;
    double diameter_mm = 0.0;  // 2 x the smaller radius of the worst pair
  };
  [[nodiscard]] Overlap worst_overlap() const;

 private:
  struct Item {
    std::uint32_t member = 0;
    std::uint32_t edge = 0;
    glm::dvec3 mid{0.0};  // the edge's middle and reach (half its length plus its radius)
    double reach = 0.0;   // when the grid was built
  };
  void build_grid() const;
  [[nodiscard]] std::uint64_t cell_key(const glm::dvec3& p) const;
  [[nodiscard]] std::size_t bucket_of(std::int64_t x, std::int64_t y, std::int64_t z) const;
  [[nodiscard]] bool excluded(const Member& a, std::size_t ea, const Member& b, std::size_t eb) const;
  template <typename Fn>
  void for_neighbours(const glm::dvec3& p, Fn&& fn) const;

  double margin_;
  std::vector<Member> members_;
  double cell_mm_ = 1.0;
  double max_radius_mm_ = 0.0;
  // Hash grid, rebuilt at every gather: bucket b holds items_[start_[b] .. start_[b + 1]).
  mutable std::vector<std::uint32_t> start_;
  mutable std::vector<Item> items_;
  mutable std::vector<std::uint32_t> bucket_of_item_;
  mutable std::vector<Item> scratch_;
  mutable std::vector<std::uint32_t> fill_;
  mutable std::vector<std::uint32_t> seen_;  // per bucket: the last query that visited it
  mutable std::uint32_t query_ = 0;
  std::size_t bucket_mask_ = 0;
};

}  // namespace cathbox::tool
