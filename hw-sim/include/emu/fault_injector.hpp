#pragma once
// Deterministic fault injection (seeded): interrupt reports dropped, delayed, duplicated or
// corrupted on their way in either direction, and encoder noise on the A/B lines.
#include <cstdint>
#include <random>
#include <span>

namespace cathbox::emu {

struct LinkFaults {
  double drop = 0;       // probability a report is lost
  double duplicate = 0;  // probability it is delivered twice
  double corrupt = 0;    // probability one random bit of it flips
  double delay = 0;      // probability it is held back by delay_us (so it may be reordered)
  uint64_t delay_us = 0;
};

struct EncoderNoise {
  double bounce = 0;  // per transition: one line toggles and toggles back (two legal edges)
  double skip = 0;    // per transition inside a run: the sample between two edges is missed
};

struct FaultCounts {
  uint64_t dropped = 0;
  uint64_t duplicated = 0;
  uint64_t corrupted = 0;
  uint64_t delayed = 0;
  uint64_t bounces = 0;
  uint64_t skips = 0;
};

// Pretends to be a box of another protocol major version: byte 1 of a report rewritten and its
// CRC made valid again (nothing if `version` is this protocol's).
void rewrite_wire_version(std::span<uint8_t> report, uint8_t version);

class FaultInjector {
 public:
  explicit FaultInjector(uint64_t seed = 1) : rng_(seed) {}
  LinkFaults in;   // box -> host
  LinkFaults out;  // host -> box
  EncoderNoise encoder;

  struct Decision {
    int copies = 1;         // 0 dropped, 1, or 2 duplicated
    uint64_t delay_us = 0;  // hold back this long
  };
  // Decides the fate of one report and corrupts it in place when chosen.
  [[nodiscard]] Decision apply(const LinkFaults& faults, std::span<uint8_t> report);
  [[nodiscard]] bool chance(double p);
  [[nodiscard]] uint32_t uniform(uint32_t n) { return static_cast<uint32_t>(rng_() % n); }
  [[nodiscard]] const FaultCounts& counts() const { return counts_; }
  FaultCounts& mutable_counts() { return counts_; }

 private:
  std::mt19937_64 rng_;
  FaultCounts counts_;
};

}  // namespace cathbox::emu
