#pragma once
// Contacts between rods, and between the far parts of one rod: the loops of a coil against
// each other, against earlier coils, against the microcatheter's tip and against an inflated
// balloon (a member whose edges take its radius, touching coils only). Edges are capsules
// (the segment between two nodes swept by the node radius); two edges closer than the sum of
// their radii plus a margin give each side a contact plane (RodObstacles). Another rod is
// frozen while one is solved, so its side of the gap is the plane; two parts of the same rod
// each take half of the gap. Candidate pairs come from a hash grid of the edges' midpoints
// (O(edges)) and are kept as a Verlet list: pairs within the contact reach plus a skin are
// listed, and the list serves every gather until an edge's middle has moved half the skin
// from where it was listed or the members change. A build then lists again only the edges
// that moved a quarter of the skin or came into a member, pairs being classified on the listed
// middles, and keeps the pairs of the others (released coils at rest). It lists all only when
// the members change: members whose edge ranges alone moved keep their edges' places, pairs and
// bounds. A member may list edges before its first gathered one (Member::listed_first: a coil's,
// from a block boundary inside its catheter), so that its first edge moving within them (a node
// crossing the catheter's tip, every node spacing of a push) changes no list. prepare() builds
// ahead, between ticks, before the gathers have to.
// A gather then tests only the listed pairs, and skips the segment test of a pair whose last
// tested distance, less what the ends of both edges can have moved since, keeps it out of
// reach (each edge's move bounded by its drift from a reference that follows it: Span). The
// two sides of a contact of a rod with itself come from one segment test (from its lower
// edge): one plane, normals opposite. The contacts are those of a fresh search.
// Nothing allocates once the members are set and the list has reached its working size.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
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
    bool self_only = false;       // with itself and with no other member (a lone tool)
    // Edges of this member within this depth past the rod's entry do not touch `hollow`: they
    // are still in its lumen (the coil leaving the microcatheter's tip).
    double hollow_depth_mm = 0.0;
    const Rod* hollow = nullptr;
    bool coil = false;            // a coil (attached past its detachment zone, or released)
    // > 0: every edge of this member is a capsule of this radius, touching coil members only,
    // their contact law (their contact stiffness) on both sides: an inflated balloon's working
    // length. A change of this alone keeps the candidate list (growth counts as motion).
    double radius_mm = 0.0;
    // Never gathered here: a rod solved elsewhere, read as it stands (the released coils' views
    // in the attached tools' field, the tools' views in the released coils'). Pairs of two such
    // members' edges serve no gather and are not listed; worst_overlap still finds them.
    bool frozen = false;
    // Edges [listed_first, edge_first) are listed too but never gathered nor reported (npos or
    // edge_first or more: none). A coil's free part begins at its catheter's tip and gains an edge
    // every node spacing it is pushed (0.5 mm, 25 ticks at 20 mm/s); listed from a boundary that
    // moves by 16 edges at a time, the list stays valid across 15 of every 16 such crossings
    // instead of being carried over and built again in the tick.
    std::size_t listed_first = static_cast<std::size_t>(-1);
    [[nodiscard]] std::size_t list_begin() const { return std::min(listed_first, edge_first); }
  };

  explicit RodContactField(double margin_mm = 0.05, double skin_mm = 0.3) : margin_(margin_mm), skin_(skin_mm) {}

  // The rods taking part in this step (positions are read at each gather). Members equal to
  // the present ones (but for radius_mm) keep the candidate list.
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

  // Between ticks: builds the candidate list now when some item's middle has moved more than
  // `fraction` of what the list covers (half the skin), so that the next tick's gathers need not.
  // True when it built.
  bool prepare(double fraction) const;
  // Times the candidate list was built (diagnostics, benches).
  [[nodiscard]] std::uint64_t list_builds() const { return list_builds_; }
  // Times the members' edge ranges moved and the list was carried over to them, and the edges
  // the last build listed again, of items() (diagnostics, tests).
  [[nodiscard]] std::uint64_t list_carries() const { return list_carries_; }
  [[nodiscard]] std::size_t relisted_by_last_build() const { return relisted_count_; }
  [[nodiscard]] std::size_t items() const { return items_.size(); }
  // Pairs the last build listed (diagnostics, tests).
  [[nodiscard]] std::size_t listed_pairs() const { return halves_.size(); }
  // Gathers made (diagnostics, benches).
  [[nodiscard]] std::uint64_t gather_calls() const { return gather_calls_; }
  // Segment tests the gathers made (diagnostics, benches).
  [[nodiscard]] std::uint64_t pair_tests() const { return pair_tests_; }

 private:
  struct Item {
    std::uint32_t member = 0;
    std::uint32_t edge = 0;
    double radius = 0.0;  // the edge's (the mean of its nodes')
  };
  // An item's terms in the gather's cull (LastGap), apart from the pair loop's reads: its drift
  // (the farther end's distance from its reference ends) and base (how far the reference has
  // moved in all, each move taken when the drift passes a tenth of the margin), as base + drift
  // and base - drift. An end has moved between two gathers by at most the drifts at both and the
  // reference's moves between them.
  struct Span {
    double far = 0.0;
    double near = 0.0;
  };
  // An item's middle now and its reach (half its length plus its radius), apart from the rest of
  // it: the gather's pair loop reads only these for every listed pair (32 bytes, two a line).
  struct Ball {
    glm::dvec3 mid{0.0};
    double reach = 0.0;
  };
  // Sets the present middles of every item and its cull terms (Span, its reference moved once it
  // drifted kRebaseMargins); false when the candidate list does not cover the middles.
  // `share` < 1: whether it covers them with that share of its room to spare (prepare).
  [[nodiscard]] bool update_mids(double share = 1.0) const;
  // Whether gathers read the item (not an edge before its member's first: Member::listed_first).
  [[nodiscard]] bool gathered(const Item& item) const { return item.edge >= members_[item.member].edge_first; }
  void set_radii(std::span<const Member> members);  // the radius overrides of the present members
  void list_items();  // the items of the present members, the grid sized for them
  [[nodiscard]] bool ranges_moved(std::span<const Member> members) const;  // only their edge ranges differ
  void carry_list_over(std::span<const Member> members);
  void update_cell();
  void build_grid(bool listed) const;  // the hash grid of the listed (or the present) middles
  // Items moved more than `share` of the skin are listed again; false: every item (a full build).
  [[nodiscard]] bool relist_moved(double share) const;
  // A gather's build lists again the items moved a quarter of the skin, half what the list covers.
  static constexpr double kRelistShare = 0.25;
  void build_list(double share = kRelistShare) const;
  void keep_last_gaps() const;  // after a partial build: the last gaps of pairs listed again
  [[nodiscard]] std::size_t bucket_of(std::int64_t x, std::int64_t y, std::int64_t z) const;
  [[nodiscard]] bool excluded_always(const Member& a, std::size_t ea, const Member& b, std::size_t eb) const;
  [[nodiscard]] bool any_frozen() const;
  [[nodiscard]] bool excluded_now(const Member& a, std::size_t ea, const Member& b, std::size_t eb) const;
  template <typename Fn>
  void for_neighbours(const glm::dvec3& p, Fn&& fn) const;  // fn(item)
  template <typename Fn>
  void for_neighbour_slots(const glm::dvec3& p, Fn&& fn) const;  // fn(slot in grid_)
  template <typename Fn>
  void for_candidates(const Member& me, std::uint32_t mi, double margin, Fn&& fn) const;

  // The cull's reference follows an edge that drifted this many margins from it (a reference
  // moved often keeps the bound near the path an edge took: a pushed coil's, or a settling one's).
  static constexpr double kRebaseMargins = 0.1;

  double margin_;
  double skin_;
  std::vector<Member> members_;
  std::vector<std::uint32_t> first_item_;  // per member: index of its first item
  std::vector<std::size_t> node_totals_;   // per member: the rod's node count when set
  double cell_mm_ = 1.0;
  double max_edge_mm_ = 0.0;
  double max_radius_mm_ = 0.0;       // of the members' own edges
  double max_override_mm_ = 0.0;     // of the radius overrides
  // Per member: the radius override the list was built with; the most any override has grown
  // since (the list covers the middles' motion plus this).
  mutable std::vector<double> listed_radius_;
  mutable double grown_mm_ = 0.0;
  // Items in member order, edges rising; their middles are updated at every gather.
  mutable std::vector<Item> items_;
  mutable std::vector<Ball> balls_;  // per item
  mutable std::vector<glm::dvec3> listed_mid_;  // the middles when the list was built
  mutable std::vector<glm::dvec3> ref_end_;    // the cull's reference ends (2 per item)
  mutable std::vector<double> ref_moved_;       // per item: its reference's moves summed (Span's base)
  mutable std::vector<Span> spans_;             // per item
  mutable bool list_valid_ = false;
  mutable bool carried_ = false;  // carried over to moved ranges: the next gather builds
  mutable std::uint64_t list_builds_ = 0;
  std::uint64_t list_carries_ = 0;
  // carry_list_over's scratch: the members and items before, the listed places and the cull's
  // references in the new order.
  std::vector<Member> members_before_;
  std::vector<std::uint32_t> first_before_;
  std::vector<glm::dvec3> carried_mid_, carried_end_;
  std::vector<double> carried_moved_;
  mutable std::uint64_t gather_calls_ = 0;
  mutable std::uint64_t pair_tests_ = 0;
  // Candidate list: item i's candidates are pairs_[pair_start_[i] .. pair_start_[i + 1]), rising.
  mutable std::vector<std::uint32_t> pair_start_;
  mutable std::vector<std::uint32_t> pairs_;
  // Per slot: the pair's segment distance when last tested plus both items' Span::near then:
  // less their Span::far now, a lower bound on their distance now.
  struct LastGap {
    double bound_mm = -std::numeric_limits<double>::infinity();  // not tested since it was listed
  };
  mutable std::vector<LastGap> last_gap_;
  // The last build's lists and gaps, while a partial build carries the kept pairs' gaps over.
  mutable std::vector<std::uint32_t> kept_start_, kept_pairs_;
  mutable std::vector<LastGap> kept_gap_;
  mutable bool relisted_all_ = true;
  // Per slot: the slot of the same pair in the other item's list, and, for a pair of one rod's
  // edges, what the gather stamped `stamp` found from the lower edge (the contact it made in
  // the output, or none, and the closest point's parameter on the higher edge).
  static constexpr std::uint32_t kNoContact = 0xffffffffu;
  struct LowerSide {
    std::uint32_t stamp = 0;
    std::uint32_t contact = kNoContact;
    double t = 0.0;
  };
  mutable std::vector<std::uint32_t> mirror_;
  mutable std::vector<LowerSide> lower_side_;
  mutable std::uint32_t gathers_ = 0;  // the stamp of the last gather: rises across builds
  using Half = std::pair<std::uint32_t, std::uint32_t>;
  mutable std::vector<Half> halves_;  // the last build's pairs, lower item first, rising
  mutable std::vector<Half> fresh_, lower_, merged_;  // a build's new pairs, and a merge
  mutable std::vector<std::uint8_t> relisted_;        // per item: listed again by this build
  mutable std::size_t relisted_count_ = 0;
  mutable std::vector<std::uint32_t> next_;                              // a build's fill positions
  // Hash grid for a build: bucket b holds the items grid_[start_[b] .. start_[b + 1]).
  mutable std::vector<std::uint32_t> start_;
  mutable std::vector<std::uint32_t> grid_;
  // The listed middles and reaches in grid_'s order (a build's broad phase reads them in a run per
  // bucket instead of gathering each candidate's from the item arrays).
  mutable std::vector<Ball> grid_balls_;
  mutable std::vector<std::uint32_t> bucket_of_item_;
  mutable std::vector<std::uint32_t> fill_;
  mutable std::vector<std::uint32_t> seen_;  // per bucket: the last query that visited it
  mutable std::uint32_t query_ = 0;
  std::size_t bucket_mask_ = 0;
};

}  // namespace cathbox::tool
