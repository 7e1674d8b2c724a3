#include "emu/fault_injector.hpp"

#include "protocol/cbx_protocol.h"

namespace cathbox::emu {

void rewrite_wire_version(std::span<uint8_t> report, uint8_t version) {
  if (version == CBX_PROTOCOL_VERSION || report.size() != CBX_REPORT_SIZE) return;
  report[1] = version;
  cbx_report_finish(report.data());
}

bool FaultInjector::chance(double p) {
  if (p <= 0) return false;
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < p;
}

FaultInjector::Decision FaultInjector::apply(const LinkFaults& faults, std::span<uint8_t> report) {
  Decision d;
  if (chance(faults.drop)) {
    ++counts_.dropped;
    d.copies = 0;
    return d;
  }
  if (chance(faults.corrupt) && !report.empty()) {
    const uint32_t bit = uniform(static_cast<uint32_t>(report.size() * 8));
    report[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
    ++counts_.corrupted;
  }
  if (chance(faults.duplicate)) {
    ++counts_.duplicated;
    d.copies = 2;
  }
  if (chance(faults.delay)) {
    ++counts_.delayed;
    d.delay_us = faults.delay_us;
  }
  return d;
}

}  // namespace cathbox::emu
