// The rod-contact field's candidate list: the present middles and whether the list still covers
// them (with each edge's cull reference), the hash grid, the (partial) rebuild of the listed pairs
// with their kept bounds, and the list carried over to members whose edge ranges moved.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include <glm/geometric.hpp>

#include "rod_contact_grid.hpp"
#include "tool/rod_contact_field.hpp"

namespace cathbox::tool {

using rod_contact_detail::apart;
using rod_contact_detail::assign_grown;
using rod_contact_detail::resize_grown;

bool RodContactField::update_mids(double share) const {
  // An edge's middle that moved less than half the skin since the list was built keeps every
  // pair within the contact reach among the listed ones (two middles close by at most the skin).
  // A radius override grown since the build (an inflating balloon) takes its share of the room.
  const double half = share * 0.5 * skin_;
  const double room = half - grown_mm_;
  const double limit_sq = grown_mm_ > 0.0 ? room * room : half * half;
  const double rebase = kRebaseMargins * margin_;
  bool covered = list_valid_ && !carried_ && room > 0.0;
  for (std::size_t i = 0; i < items_.size(); ++i) {
    const Item& item = items_[i];
    const std::span<const glm::dvec3> x = members_[item.member].rod->positions();
    const glm::dvec3& p0 = x[item.edge];
    const glm::dvec3& p1 = x[item.edge + 1];
    balls_[i].mid = 0.5 * (p0 + p1);
    // An edge listed but not gathered (Member::listed_first) needs no cover until it is gathered.
    if (covered && gathered(item)) {
      const glm::dvec3 d = balls_[i].mid - listed_mid_[i];
      covered = glm::dot(d, d) <= limit_sq;
    }
    // The cull's reference follows the edge once it has drifted a tenth of the margin (none
    // yet, NaN: an edge new to the field takes its ends).
    glm::dvec3& r0 = ref_end_[2 * i];
    glm::dvec3& r1 = ref_end_[2 * i + 1];
    double drift = std::sqrt(std::max(glm::dot(p0 - r0, p0 - r0), glm::dot(p1 - r1, p1 - r1)));
    if (!(drift <= rebase)) {
      if (std::isfinite(drift)) ref_moved_[i] += drift;
      r0 = p0;
      r1 = p1;
      drift = 0.0;
    }
    spans_[i] = Span{ref_moved_[i] + drift, ref_moved_[i] - drift};
  }
  return covered;
}

bool RodContactField::prepare(double fraction) const {
  if (members_.empty() || items_.empty() || update_mids(fraction)) return false;
  // Listed again: the items moved more than half the trigger, as a build in a gather lists those
  // moved a quarter of the skin, half its trigger (a lower share lists again, a tick or two later,
  // the items the last build kept).
  build_list(kRelistShare * fraction);
  return true;
}

void RodContactField::build_grid(bool listed) const {
  const std::size_t buckets = bucket_mask_ + 1;
  const std::size_t n = items_.size();
  std::fill(start_.begin(), start_.begin() + static_cast<std::ptrdiff_t>(buckets + 1), 0u);
  bucket_of_item_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 c = glm::floor((listed ? listed_mid_[i] : balls_[i].mid) / cell_mm_);
    const std::size_t b = bucket_of(static_cast<std::int64_t>(c.x), static_cast<std::int64_t>(c.y),
                                    static_cast<std::int64_t>(c.z));
    bucket_of_item_.push_back(static_cast<std::uint32_t>(b));
    ++start_[b + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  // Counting sort of the item indices by bucket.
  fill_.assign(start_.begin(), start_.begin() + static_cast<std::ptrdiff_t>(buckets));
  grid_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) grid_[fill_[bucket_of_item_[i]]++] = i;
  if (!listed) return;
  grid_balls_.resize(n);
  for (std::size_t k = 0; k < n; ++k) grid_balls_[k] = Ball{listed_mid_[grid_[k]], balls_[grid_[k]].reach};
}

// Items whose middle left its listed place by more than a quarter of the skin (every item when
// the members changed) are listed again where they are now.
bool RodContactField::relist_moved(double share) const {
  const std::size_t n = items_.size();
  // A grown radius override relists every item (its pairs' classification used the old reach).
  const bool partial = list_valid_ && listed_mid_.size() == n && !(grown_mm_ > 0.0);
  for (std::size_t mi = 0; mi < members_.size(); ++mi) listed_radius_[mi] = members_[mi].radius_mm;
  grown_mm_ = 0.0;
  listed_mid_.resize(n);
  relisted_.assign(n, 1);
  relisted_count_ = 0;
  const double keep_sq = share * share * skin_ * skin_;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 d = balls_[i].mid - listed_mid_[i];
    if (partial && glm::dot(d, d) <= keep_sq) {
      relisted_[i] = 0;
      continue;
    }
    ++relisted_count_;
    listed_mid_[i] = balls_[i].mid;
  }
  return partial;
}

void RodContactField::build_list(double share) const {
  ++list_builds_;
  carried_ = false;
  const std::size_t n = items_.size();
  relisted_all_ = !relist_moved(share);
  if (relisted_all_) halves_.clear();  // the members changed: no pair is kept
  build_grid(true);
  // Each pair is classified on the two items' listed middles: a pair left out is further apart
  // than the reach plus the margin and the skin there, and each item stays within half the skin
  // of its listed middle until the next build, so it cannot come into reach. Pairs of two items
  // not listed again are kept from the last build; a relisted item's pairs are found afresh:
  // with higher items (`fresh_`, in rising order per item, as the lists need them) and with
  // lower items kept in place (`lower_`, sorted after).
  std::erase_if(halves_, [&](const auto& h) { return relisted_[h.first] != 0 || relisted_[h.second] != 0; });
  fresh_.clear();
  lower_.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    if (relisted_[i] == 0) continue;
    const std::size_t from = fresh_.size();
    const Item& a = items_[i];
    const Member& ma = members_[a.member];
    const glm::dvec3 mid = listed_mid_[i];
    const double reach = balls_[i].reach;
    for_neighbour_slots(mid, [&](std::uint32_t slot) {
      const Ball& other = grid_balls_[slot];
      if (apart(mid, reach, other.mid, other.reach, margin_ + skin_)) return;
      const std::uint32_t j = grid_[slot];
      if (j == i || (j < i && relisted_[j] != 0)) return;  // the lower relisted item found it
      const Item& b = items_[j];
      const Member& mb = members_[b.member];
      if (ma.frozen && mb.frozen) return;  // no gather reads the pair
      if (excluded_always(ma, a.edge, mb, b.edge)) return;
      if (j > i) fresh_.push_back({i, j});
      else lower_.push_back({j, i});
    });
    std::sort(fresh_.begin() + static_cast<std::ptrdiff_t>(from), fresh_.end());
  }
  std::sort(lower_.begin(), lower_.end());
  merged_.clear();
  std::merge(halves_.begin(), halves_.end(), fresh_.begin(), fresh_.end(), std::back_inserter(merged_));
  halves_.clear();
  std::merge(merged_.begin(), merged_.end(), lower_.begin(), lower_.end(), std::back_inserter(halves_));
  const bool partial = !relisted_all_;
  if (partial) {
    kept_start_.swap(pair_start_);
    kept_pairs_.swap(pairs_);
    kept_gap_.swap(last_gap_);
  }
  assign_grown(pair_start_, n + 1, 0u);
  for (const auto& [i, j] : halves_) ++pair_start_[i + 1], ++pair_start_[j + 1];
  for (std::size_t i = 0; i < n; ++i) pair_start_[i + 1] += pair_start_[i];
  // Item k receives its lower partners (while they are filled, in rising order) before its own
  // higher ones: each list comes out sorted.
  pairs_.resize(pair_start_[n]);
  mirror_.resize(pair_start_[n]);
  next_.assign(pair_start_.begin(), pair_start_.end() - 1);
  for (const auto& [i, j] : halves_) {
    mirror_[next_[i]] = next_[j];
    mirror_[next_[j]] = next_[i];
    pairs_[next_[i]++] = j;
    pairs_[next_[j]++] = i;
  }
  if (partial) {
    keep_last_gaps();
  } else {
    assign_grown(last_gap_, pairs_.size(), LastGap{});
  }
  // A slot's lower side from before this build carries an earlier gather's stamp, which no later
  // gather takes for its own (the stamps only rise): the sides need no clearing, only room.
  resize_grown(lower_side_, pairs_.size());
  list_valid_ = true;
}

// A pair listed again keeps its last tested bound: it holds whatever the list does, each item's
// drift and reference being its own (without it the gathers after a build tested every pair of
// the items listed again); a new pair is untested. Both lists of an item are sorted: one merge
// walk, which writes every slot.
void RodContactField::keep_last_gaps() const {
  const std::size_t n = items_.size();
  resize_grown(last_gap_, pairs_.size());  // every slot written below
  for (std::size_t i = 0; i < n; ++i) {
    const bool kept = i + 1 < kept_start_.size();
    std::uint32_t o = kept ? kept_start_[i] : 0;
    const std::uint32_t o_end = kept ? kept_start_[i + 1] : 0;
    for (std::uint32_t p = pair_start_[i]; p < pair_start_[i + 1]; ++p) {
      const std::uint32_t j = pairs_[p];
      while (o < o_end && kept_pairs_[o] < j) ++o;
      last_gap_[p] = o < o_end && kept_pairs_[o] == j ? kept_gap_[o] : LastGap{};
    }
  }
}

// The members' edge ranges moved: an edge that stays keeps its listed place, its cull reference,
// its pairs with the others that stay and their last bounds (the same pairs a partial build
// keeps: an edge's index on its rod is unchanged, and the items keep their order); an edge that
// comes in is listed by the next build, which the next gather makes. The contacts are a fresh search's either way,
// but a full build of a packed sac at each node crossing was the coil benches' slowest steps.
void RodContactField::carry_list_over(std::span<const Member> members) {
  members_before_.assign(members_.begin(), members_.end());
  first_before_.assign(first_item_.begin(), first_item_.end());
  const std::size_t n_before = items_.size();
  members_.assign(members.begin(), members.end());
  list_items();
  const std::size_t n = items_.size();
  // Old item -> new item (kNoContact: its edge left its member); a new item's listed middle is
  // infinitely far, so the build lists it.
  next_.assign(n_before, kNoContact);
  carried_mid_.assign(n, glm::dvec3(std::numeric_limits<double>::infinity()));
  carried_end_.assign(2 * n, glm::dvec3(std::numeric_limits<double>::quiet_NaN()));
  carried_moved_.assign(n, 0.0);
  for (std::uint32_t mi = 0; mi < members_.size(); ++mi) {
    const std::size_t first = members_[mi].list_begin();
    const std::size_t last = first + (first_item_[mi + 1] - first_item_[mi]);
    for (std::uint32_t i = first_before_[mi]; i < first_before_[mi + 1]; ++i) {
      const std::size_t e = members_before_[mi].list_begin() + (i - first_before_[mi]);
      if (e < first || e >= last) continue;
      const auto j = static_cast<std::uint32_t>(first_item_[mi] + (e - first));
      next_[i] = j;
      carried_mid_[j] = listed_mid_[i];
      carried_end_[2 * j] = ref_end_[2 * i];
      carried_end_[2 * j + 1] = ref_end_[2 * i + 1];
      carried_moved_[j] = ref_moved_[i];
    }
  }
  listed_mid_.swap(carried_mid_);
  ref_end_.swap(carried_end_);
  ref_moved_.swap(carried_moved_);
  std::erase_if(halves_, [&](const Half& h) { return next_[h.first] == kNoContact || next_[h.second] == kNoContact; });
  for (Half& h : halves_) h = {next_[h.first], next_[h.second]};
  // The lists and their last bounds in the new items' order (the map keeps the order, so each
  // list stays sorted), for the build to keep.
  kept_start_.assign(n + 1, 0u);
  kept_pairs_.clear();
  kept_gap_.clear();
  for (std::uint32_t i = 0; i < n_before && i + 1 < pair_start_.size(); ++i) {
    if (next_[i] == kNoContact) continue;
    const std::size_t listed = kept_pairs_.size();
    for (std::uint32_t p = pair_start_[i]; p < pair_start_[i + 1]; ++p) {
      if (next_[pairs_[p]] == kNoContact) continue;
      kept_pairs_.push_back(next_[pairs_[p]]);
      kept_gap_.push_back(last_gap_[p]);
    }
    kept_start_[next_[i] + 1] = static_cast<std::uint32_t>(kept_pairs_.size() - listed);
  }
  for (std::size_t j = 0; j < n; ++j) kept_start_[j + 1] += kept_start_[j];
  pair_start_.swap(kept_start_);
  pairs_.swap(kept_pairs_);
  last_gap_.swap(kept_gap_);
  carried_ = true;
  ++list_carries_;
}

}  // namespace cathbox::tool
