// The rod-contact field's candidate list (rod_contact_field.cpp, rod_contact_list.cpp) against
// a wide member: a build that lists the coils' edges again and keeps an inflated balloon's as they
// were still pairs them wherever the balloon's reach puts its edges' middles.
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "analytic_walls.hpp"
#include "collision/segment_pair.hpp"
#include "rod_test_support.hpp"
#include "tool/rod_contact_field.hpp"

namespace cathbox::tool {
namespace {

using testing::member_of;

// A straight rod of outer diameter `od` along +z from `at`, `length` mm of it inserted.
Rod straight(const glm::dvec3& at, double od, double length) {
  Rod rod(testing::uniform_tool(length + 10.0, od, 20.0, 15.0, 0.5, 0.0));
  rod.set_entry(at, {0.0, 0.0, 1.0});
  const testing::NoWall wall;
  testing::insert_to(rod, wall, length, 0.5);
  return rod;
}

// The pairs of an edge of `a` and an edge of `b` (their members' ranges) closer than `reach_mm`,
// by brute force: the contacts a gather of `a` against `b` alone makes.
std::size_t pairs_within(const RodContactField::Member& a, const RodContactField::Member& b, double reach_mm) {
  std::size_t n = 0;
  const auto x = a.rod->positions();
  const auto y = b.rod->positions();
  for (std::size_t e = a.edge_first; e < a.edge_last; ++e) {
    for (std::size_t f = b.edge_first; f < b.edge_last; ++f) {
      const collision::SegmentPair p = collision::closest_segment_segment(x[e], x[e + 1], y[f], y[f + 1]);
      n += std::sqrt(p.distance_sq) < reach_mm ? 1 : 0;
    }
  }
  return n;
}

TEST(RodContactField, APartialBuildPairsACoilWithAWideMemberKeptAsListed) {
  // An inflated balloon's working length (every edge a 2 mm capsule) on a shaft along z from 0 to
  // 20 mm, and two coil-sized rods (0.25 mm) pushed in alongside from z = -12: one 2.15 mm from
  // its axis (within the two radii and the margin, 2.175 mm), one 2.30 mm on the other side
  // (not): the balloon's edges' middles lie farther from a coil's than two coil edges' reach.
  // Pushed in, the coils' edges are listed again while the balloon's stay as listed.
  Rod shaft = straight({-0.5, 0.0, 0.0}, 0.5, 20.0);
  Rod near = straight({1.65, 0.0, -12.0}, 0.25, 5.0);
  Rod far = straight({-2.8, 0.0, -12.0}, 0.25, 5.0);
  RodContactField field(0.05, 0.3);
  const auto set_members = [&] {
    const std::vector<RodContactField::Member> members{member_of(shaft, false, 2.0), member_of(near, true, 0.0),
                                                       member_of(far, true, 0.0)};
    field.set_members(members);
  };
  set_members();
  std::vector<EdgeContact> out;
  field.gather(near, out);
  EXPECT_TRUE(out.empty()) << "the coils start short of the balloon";
  const testing::NoWall wall;
  for (double ins = 5.5; ins <= 25.0; ins += 0.5) {
    testing::insert_to(near, wall, ins, 0.5);
    testing::insert_to(far, wall, ins, 0.5);
    set_members();
    field.gather(near, out);
  }
  EXPECT_GT(field.list_builds(), 1u);
  EXPECT_LT(field.relisted_by_last_build(), field.items()) << "the last build listed every edge again";
  // Every pair of a coil edge and a balloon edge within the two radii and the margin.
  const std::size_t expected = pairs_within(member_of(near, true, 0.0), member_of(shaft, false, 2.0), 2.0 + 0.125 + 0.05);
  EXPECT_GT(expected, 10u);
  EXPECT_EQ(out.size(), expected) << "the coil beside the balloon touches it along its length";
  for (const EdgeContact& c : out) EXPECT_GT(c.normal.x, 0.99) << "edge " << c.edge;
  field.gather(far, out);
  EXPECT_TRUE(out.empty()) << out.size() << " contacts 2.30 mm from the balloon's axis";
  field.gather(shaft, out);
  EXPECT_EQ(out.size(), expected) << "the balloon's side of the same contacts";
  for (const EdgeContact& c : out) EXPECT_LT(c.normal.x, -0.99) << "edge " << c.edge;
}

TEST(RodContactField, PairsOfTwoFrozenMembersAreNotListedButStillCountInTheWorstOverlap) {
  // Two coil-sized rods (0.25 mm) side by side, 0.20 mm apart (0.05 mm deep into each other), and
  // a third alongside them, 0.28 mm from the first (a gap of 0.03 mm: in the margin's reach).
  // Frozen, the two side by side are read, never gathered: their pairs are not listed, while every
  // pair of the third with them is, as in a field with none frozen.
  Rod a = straight({0.0, 0.0, 0.0}, 0.25, 10.0);
  Rod b = straight({0.20, 0.0, 0.0}, 0.25, 10.0);
  Rod c = straight({-0.28, 0.0, 0.0}, 0.25, 10.0);
  const auto fields_members = [&](bool frozen) {
    std::vector<RodContactField::Member> members{member_of(a, true, 0.0), member_of(b, true, 0.0), member_of(c, true, 0.0)};
    members[0].frozen = members[1].frozen = frozen;
    return members;
  };
  RodContactField with(0.05, 0.3), without(0.05, 0.3);
  with.set_members(fields_members(true));
  without.set_members(fields_members(false));
  std::vector<EdgeContact> got, expected;
  with.gather(c, got);
  without.gather(c, expected);
  ASSERT_EQ(got.size(), expected.size());
  EXPECT_EQ(got.size(), pairs_within(member_of(c, true, 0.0), member_of(a, true, 0.0), 0.25 + 0.05));
  EXPECT_GT(got.size(), 10u);
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].edge, expected[k].edge);
    EXPECT_EQ(got[k].normal, expected[k].normal);
    EXPECT_EQ(got[k].offset_mm, expected[k].offset_mm);
  }
  // The listed pairs are those of a field without frozen members less exactly those a field of a
  // and b alone lists.
  RodContactField pair_only(0.05, 0.3);
  const std::vector<RodContactField::Member> ab{member_of(a, true, 0.0), member_of(b, true, 0.0)};
  pair_only.set_members(ab);
  pair_only.gather(a, expected);
  EXPECT_GT(pair_only.listed_pairs(), 20u);
  EXPECT_EQ(with.listed_pairs() + pair_only.listed_pairs(), without.listed_pairs());
  // The deepest overlap is the frozen pair's, found as in the field without frozen members.
  const RodContactField::Overlap worst = with.worst_overlap();
  EXPECT_NEAR(worst.depth_mm, 0.05, 1e-9);
  EXPECT_EQ(worst.depth_mm, without.worst_overlap().depth_mm);
}

}  // namespace
}  // namespace cathbox::tool
