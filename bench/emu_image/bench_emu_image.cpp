// bench_emu_image: how fast the emulated STM32F411 runs the shipped firmware image
// (cathbox-emu --image), against the peer that runs the same firmware core natively on a
// simulated board (cathbox-emu's default box). Each iteration advances 1 s of virtual time of a
// booted, enumerated box streaming its state reports (10 kHz tick, 1 kHz USB frames), in
// process, without a socket client.
// Counters: emulated instructions per wall second (MIPS), the real-time factor (virtual s per
// wall s; > 1 is faster than the chip), CPU s per virtual s (the gate: <= 1), and the
// image's worst SysTick handler in instructions (the tick-cost budget is 2000).
// The image: $CATHBOX_FIRMWARE_IMAGE, else build/stm32f411/bin/stm32f411_firmware.bin.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "emu/emulator.hpp"
#include "emu/image_emulator.hpp"

namespace {

constexpr uint64_t kVirtual_us = 1'000'000;

std::vector<uint8_t> firmware_image() {
  const char* env = std::getenv("CATHBOX_FIRMWARE_IMAGE");
  const std::string path =
      env != nullptr && *env != '\0' ? env : std::string(CATHBOX_SOURCE_DIR) + "/build/stm32f411/bin/stm32f411_firmware.bin";
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

double cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

// Wall and CPU time of `advance` over the benchmark's iterations, as counters.
template <class Advance>
void time_virtual_seconds(benchmark::State& bench, Advance&& advance) {
  double wall = 0;
  double cpu = 0;
  for (auto _ : bench) {
    const auto w0 = std::chrono::steady_clock::now();
    const double c0 = cpu_s();
    advance();
    cpu += cpu_s() - c0;
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  }
  const double virtual_s = static_cast<double>(bench.iterations()) * static_cast<double>(kVirtual_us) * 1e-6;
  bench.counters["realtime_factor"] = virtual_s / wall;
  bench.counters["cpu_s_per_virtual_s"] = cpu / virtual_s;
}

void WholeImage(benchmark::State& bench) {
  const auto image = firmware_image();
  auto created = cathbox::emu::ImageEmulator::create(image);
  if (!created) {
    bench.SkipWithError(("no firmware image (scripts/build stm32f411): " + created.error().message).c_str());
    return;
  }
  auto& box = *created.value();
  box.advance(300'000);  // boot and enumeration
  if (!box.enumerated()) {
    bench.SkipWithError(("the image did not enumerate: " + box.enumeration_error() + box.error()).c_str());
    return;
  }
  const uint64_t instructions0 = box.machine().instructions();
  double wall = 0;
  time_virtual_seconds(bench, [&] {
    const auto w0 = std::chrono::steady_clock::now();
    box.advance(kVirtual_us);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  });
  if (!box.error().empty()) bench.SkipWithError(box.error().c_str());
  bench.counters["emulated_MIPS"] = static_cast<double>(box.machine().instructions() - instructions0) / wall * 1e-6;
  bench.counters["tick_instr_max"] = static_cast<double>(box.machine().tick_instructions_max());
  bench.counters["ticks_per_virtual_s"] =
      static_cast<double>(box.machine().ticks()) / (static_cast<double>(box.now_us()) * 1e-6);
}
BENCHMARK(WholeImage)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

// Peer: the same firmware core compiled for the host on cathbox-emu's simulated board.
void PeerCoreOnSimulatedBoard(benchmark::State& bench) {
  cathbox::emu::Emulator box{cathbox::emu::EmuOptions{}};
  box.advance(300'000);
  time_virtual_seconds(bench, [&] { box.advance(kVirtual_us); });
}
BENCHMARK(PeerCoreOnSimulatedBoard)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
