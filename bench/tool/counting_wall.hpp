#pragma once
// A wall that counts (and optionally keeps) the probes the rods make of the wall it wraps.
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "tool/wall_model.hpp"

namespace cathbox::bench {

// One wall probe as a rod made it: which node (its hint), where, and in which step.
struct ProbeRecord {
  std::uint32_t node;
  std::uint32_t step;
  tool::WallProbe probe;
};

// Counts the wall probes the rods make (the mesh wall's closest-point and contact queries),
// passing each to the wall it wraps; keeps them when given a record.
class CountingWall final : public tool::WallModel {
 public:
  explicit CountingWall(const tool::WallModel& inner) : inner_(inner) {}
  [[nodiscard]] std::shared_ptr<const tool::WallSurface> surface() const override { return inner_.surface(); }
  [[nodiscard]] bool probe(const tool::WallProbe& probe, tool::WallHint& hint, tool::WallContact& out) const override {
    ++probes_;
    if (record_ != nullptr) {
      const auto [it, fresh] = nodes_.try_emplace(&hint, static_cast<std::uint32_t>(nodes_.size()));
      record_->push_back({it->second, step_, probe});
    }
    return inner_.probe(probe, hint, out);
  }
  [[nodiscard]] std::uint64_t probes() const { return probes_; }
  void record(std::vector<ProbeRecord>* out) { record_ = out; }
  void next_step() { ++step_; }
  [[nodiscard]] std::size_t nodes() const { return nodes_.size(); }

 private:
  const tool::WallModel& inner_;
  mutable std::uint64_t probes_ = 0;
  std::vector<ProbeRecord>* record_ = nullptr;
  mutable std::map<const tool::WallHint*, std::uint32_t> nodes_;  // each probed node's hint
  std::uint32_t step_ = 0;
};

}  // namespace cathbox::bench
