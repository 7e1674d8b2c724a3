// bench_collision: closest-point queries on vessel-sized meshes, ours beside Embree
// (rtcPointQuery) and FCL (distance to a tiny sphere), same mesh and the same 10,000 points
// within 2 mm of the wall; tree build time; coherent vs cold queries for tool nodes moving
// <= 0.1 mm per step; sphere contacts for a 350-node tool per step. First checks that the
// peers agree with ours on every point within their precision (exit 1 otherwise; --check-only
// stops there), then prints Google Benchmark's table and a side-by-side summary of the medians.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>

#include "collision/obb_tree.hpp"
#include "mesh_factory.hpp"
#include "peers.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cb = cathbox::collision;

namespace {

constexpr int kPoints = 10000;
constexpr int kNodes = 350;
constexpr int kSteps = 30;
constexpr double kMaxStep_mm = 0.1;

struct Case {
  std::string name;
  cathbox::vessel::SurfaceMesh mesh;
  std::vector<glm::dvec3> points;                  // within 2 mm of the wall
  std::vector<std::vector<glm::dvec3>> walks;      // [step][node], steps <= 0.1 mm
  std::optional<cb::ObbTree> tree;
  std::unique_ptr<cb::bench::PeerIndex> embree;
  std::unique_ptr<cb::bench::PeerIndex> fcl;
};

glm::dvec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return glm::normalize(glm::dvec3{g(rng), g(rng), g(rng)});
}

glm::dvec3 surface_point(const cathbox::vessel::SurfaceMesh& m, std::mt19937& rng) {
  std::uniform_int_distribution<std::size_t> pick(0, m.triangle_count() - 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t t = pick(rng);
  double a = u(rng), b = u(rng);
  if (a + b > 1.0) {
    a = 1.0 - a;
    b = 1.0 - b;
  }
  auto c = [&](int k) { return glm::dvec3(m.positions_mm[m.triangles[3 * t + static_cast<std::size_t>(k)]]); };
  return c(0) + a * (c(1) - c(0)) + b * (c(2) - c(0));
}

std::unique_ptr<Case> make_case(std::string name, cathbox::vessel::SurfaceMesh mesh) {
  auto c = std::make_unique<Case>();
  c->name = std::move(name);
  c->mesh = std::move(mesh);
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> within(0.0, 2.0);
  for (int i = 0; i < kPoints; ++i) c->points.push_back(surface_point(c->mesh, rng) + within(rng) * random_unit(rng));
  std::uniform_real_distribution<double> step(0.0, kMaxStep_mm);
  std::vector<glm::dvec3> nodes(c->points.begin(), c->points.begin() + kNodes);
  for (int s = 0; s < kSteps; ++s) {
    for (auto& p : nodes) p += step(rng) * random_unit(rng);
    c->walks.push_back(nodes);
  }
  auto built = cb::ObbTree::build(c->mesh);
  if (!built) {
    std::fprintf(stderr, "bench_collision: %s: %s\n", c->name.c_str(), built.error().message.c_str());
    std::exit(1);
  }
  c->tree = std::move(*built);
  c->embree = cb::bench::make_embree(c->mesh);
  c->fcl = cb::bench::make_fcl(c->mesh);
  return c;
}

// For the tests of the check itself: a peer whose answer at one point is made wrong.
struct Perturbation {
  std::string peer;  // "embree" or "fcl"; empty: none
  int index = -1;
};

// How far a peer's distance may be from ours: a few rounding steps of the coordinates'
// magnitude in the peer's precision. Embree works in float (the query point, the vertices and
// the closest-point arithmetic); FCL in double, like ours.
constexpr double kUlpsAllowed = 16.0;
double precision_mm(const Case& c, double epsilon) {
  double scale = 0.0;
  for (const glm::vec3& q : c.mesh.positions_mm)
    scale = std::max({scale, std::abs(static_cast<double>(q.x)), std::abs(static_cast<double>(q.y)),
                      std::abs(static_cast<double>(q.z))});
  return kUlpsAllowed * epsilon * (scale + 2.0);  // the points lie within 2 mm of the wall
}

struct Disagreement {
  const char* peer;
  double tolerance_mm;
  double worst_mm = 0.0;
  int worst_index = -1;
  int count = 0;  // points beyond the tolerance
  void add(int index, double peer_mm, double ours_mm) {
    const double d = std::abs(peer_mm - ours_mm);
    if (d > tolerance_mm) ++count;
    if (d > worst_mm || worst_index < 0) {
      worst_mm = d;
      worst_index = index;
    }
  }
};

// The three answers must agree, on every point, before their speeds mean anything: exits 1
// (before any timing) naming the case, the peer and the worst point otherwise.
void check_agreement(Case& c, const Perturbation& perturb) {
  Disagreement embree{"embree", precision_mm(c, std::numeric_limits<float>::epsilon())};
  Disagreement fcl{"fcl", precision_mm(c, std::numeric_limits<double>::epsilon())};
  std::vector<double> ours(kPoints);
  for (int i = 0; i < kPoints; ++i) {
    const glm::dvec3& p = c.points[static_cast<std::size_t>(i)];
    const auto closest = c.tree->closest_point(p);
    ours[static_cast<std::size_t>(i)] = closest ? closest->distance_mm : std::nan("");
    double e = c.embree->distance(p);
    double f = c.fcl->distance(p);
    // The check's own test: a peer answer made wrong by 4x its tolerance at one point.
    if (i == perturb.index && perturb.peer == "embree") e += 4.0 * embree.tolerance_mm;
    if (i == perturb.index && perturb.peer == "fcl") f += 4.0 * fcl.tolerance_mm;
    if (!closest) {
      std::fprintf(stderr, "bench_collision: %s: no closest point for point %d\n", c.name.c_str(), i);
      std::exit(1);
    }
    embree.add(i, e, ours[static_cast<std::size_t>(i)]);
    fcl.add(i, f, ours[static_cast<std::size_t>(i)]);
  }
  std::printf("%s: %zu triangles, %d points: largest distance difference vs Embree %.2g mm (allowed %.2g), "
              "vs FCL %.2g mm (allowed %.2g)\n",
              c.name.c_str(), c.mesh.triangle_count(), kPoints, embree.worst_mm, embree.tolerance_mm, fcl.worst_mm,
              fcl.tolerance_mm);
  for (const Disagreement* d : {&embree, &fcl}) {
    if (d->count == 0) continue;
    const glm::dvec3& p = c.points[static_cast<std::size_t>(d->worst_index)];
    std::fprintf(stderr,
                 "bench_collision: %s: %s disagrees with ours beyond its precision (%.2g mm) at %d of %d points; "
                 "worst at point %d (%.6f, %.6f, %.6f): ours %.9f mm, %s off by %.3g mm\n",
                 c.name.c_str(), d->peer, d->tolerance_mm, d->count, kPoints, d->worst_index, p.x, p.y, p.z,
                 ours[static_cast<std::size_t>(d->worst_index)], d->peer, d->worst_mm);
  }
  if (embree.count != 0 || fcl.count != 0) std::exit(1);
  // The coherent walk must give exactly the cold answers.
  std::vector<cb::QueryHint> hints(kNodes);
  std::size_t differ = 0;
  for (const auto& step : c.walks)
    for (std::size_t i = 0; i < step.size(); ++i) {
      const auto warm = c.tree->closest_point(step[i], cb::ObbTree::kNoLimit, hints[i]);
      const auto cold = c.tree->closest_point(step[i]);
      if (!warm || !cold || warm->distance_mm != cold->distance_mm) ++differ;
    }
  std::printf("%s: coherent walk vs cold: %zu of %d differ\n", c.name.c_str(), differ, kNodes * kSteps);
  if (differ != 0) std::exit(1);
}

void per_query(benchmark::State& state, double queries) {
  state.counters["ns_per_query"] =
      benchmark::Counter(queries, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void register_case(Case& c) {
  const std::string n = c.name + "/";
  benchmark::RegisterBenchmark((n + "build/ours").c_str(), [&c](benchmark::State& state) {
    for (auto _ : state) {
      auto b = cb::ObbTree::build(c.mesh);
      benchmark::DoNotOptimize(b);
    }
  })->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(5);

  benchmark::RegisterBenchmark((n + "closest/ours").c_str(), [&c](benchmark::State& state) {
    for (auto _ : state)
      for (const auto& p : c.points) benchmark::DoNotOptimize(c.tree->closest_point(p));
    per_query(state, kPoints);
  })->Unit(benchmark::kMillisecond)->Iterations(3)->Repetitions(9);

  benchmark::RegisterBenchmark((n + "closest/embree").c_str(), [&c](benchmark::State& state) {
    for (auto _ : state)
      for (const auto& p : c.points) benchmark::DoNotOptimize(c.embree->distance(p));
    per_query(state, kPoints);
  })->Unit(benchmark::kMillisecond)->Iterations(3)->Repetitions(9);

  benchmark::RegisterBenchmark((n + "closest/fcl").c_str(), [&c](benchmark::State& state) {
    for (auto _ : state)
      for (const auto& p : c.points) benchmark::DoNotOptimize(c.fcl->distance(p));
    per_query(state, kPoints);
  })->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(3);

  // A tool of 350 nodes, each moving <= 0.1 mm per step: cold queries vs coherent ones.
  benchmark::RegisterBenchmark((n + "walk/cold").c_str(), [&c](benchmark::State& state) {
    for (auto _ : state)
      for (const auto& step : c.walks)
        for (const auto& p : step) benchmark::DoNotOptimize(c.tree->closest_point(p));
    per_query(state, kNodes * kSteps);
  })->Unit(benchmark::kMillisecond)->Iterations(3)->Repetitions(9);

  benchmark::RegisterBenchmark((n + "walk/coherent").c_str(), [&c](benchmark::State& state) {
    std::vector<cb::QueryHint> hints(kNodes);
    for (std::size_t i = 0; i < hints.size(); ++i)
      benchmark::DoNotOptimize(c.tree->closest_point(c.walks[0][i], cb::ObbTree::kNoLimit, hints[i]));
    std::uint64_t hits = 0, refills = 0;
    for (auto _ : state) {
      for (const auto& step : c.walks)
        for (std::size_t i = 0; i < step.size(); ++i)
          benchmark::DoNotOptimize(c.tree->closest_point(step[i], cb::ObbTree::kNoLimit, hints[i]));
    }
    for (const auto& h : hints) {
      hits += h.hits();
      refills += h.refills();
    }
    per_query(state, kNodes * kSteps);
    state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(hits + refills);
  })->Unit(benchmark::kMillisecond)->Iterations(3)->Repetitions(9);

  // One haptic step of the tool's wall probe (closest point within radius + range = 0.7 mm,
  // with hints) for the 350 nodes.
  benchmark::RegisterBenchmark((n + "step/probe").c_str(), [&c](benchmark::State& state) {
    std::vector<cb::QueryHint> hints(kNodes);
    for (auto _ : state)
      for (const auto& step : c.walks)
        for (std::size_t i = 0; i < step.size(); ++i)
          benchmark::DoNotOptimize(c.tree->closest_point(step[i], 0.7, hints[i]));
    per_query(state, kNodes * kSteps);
  })->Unit(benchmark::kMillisecond)->Iterations(3)->Repetitions(9);

  // One haptic step of sphere contacts (r = 0.3 mm) for the 350 nodes, with hints.
  benchmark::RegisterBenchmark((n + "step/sphere_contacts").c_str(), [&c](benchmark::State& state) {
    std::vector<cb::QueryHint> hints(kNodes);
    cb::Contact out[8];
    for (auto _ : state)
      for (const auto& step : c.walks)
        for (std::size_t i = 0; i < step.size(); ++i)
          benchmark::DoNotOptimize(c.tree->sphere_contacts(step[i], 0.3, out, hints[i]));
    per_query(state, kNodes * kSteps);
    std::uint64_t hits = 0, refills = 0;
    for (const auto& h : hints) {
      hits += h.hits();
      refills += h.refills();
    }
    state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(hits + refills);
  })->Unit(benchmark::kMillisecond)->Iterations(3)->Repetitions(9);
}

// Keeps the median of every repeated benchmark, by name.
class MedianReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs)
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name == "median") {
        // CPU time: the machine may be shared, and every query runs on this one thread.
        medians[r.run_name.function_name] = r.GetAdjustedCPUTime();  // in the run's unit (ms)
        auto it = r.counters.find("hit_rate");
        if (it != r.counters.end()) hit_rates[r.run_name.function_name] = it->second.value;
      }
    ConsoleReporter::ReportRuns(runs);
  }
  std::map<std::string, double> medians;
  std::map<std::string, double> hit_rates;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  // Our options (Google Benchmark has taken its own): --check-only runs the agreement checks
  // and exits; --perturb=PEER:INDEX makes a peer's answer at one point wrong (the check's test).
  bool check_only = false;
  Perturbation perturb;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--check-only") {
      check_only = true;
    } else if (arg.rfind("--perturb=", 0) == 0 && arg.find(':') != std::string::npos) {
      const std::string value = arg.substr(10);
      perturb.peer = value.substr(0, value.find(':'));
      perturb.index = std::atoi(value.c_str() + value.find(':') + 1);
      if ((perturb.peer != "embree" && perturb.peer != "fcl") || perturb.index < 0 || perturb.index >= kPoints) {
        std::fprintf(stderr, "bench_collision: --perturb=%s: expected embree|fcl:INDEX with INDEX < %d\n",
                     value.c_str(), kPoints);
        return 2;
      }
    } else {
      std::fprintf(stderr, "bench_collision: unknown option '%s' (known: --check-only, --perturb=PEER:INDEX, "
                   "Google Benchmark's --benchmark_*)\n", arg.c_str());
      return 2;
    }
  }
  std::vector<std::unique_ptr<Case>> cases;
  // The largest bundled case at subdivision levels 2 and 3, and a 100k-triangle knot-shaped
  // vessel tube (the build-time reference size).
  for (int level : {2, 3}) {
    cathbox::vessel::MeshOptions options;
    options.subdivision_level = level;
    auto loaded = cathbox::vessel::load_surface_mesh(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.hclm", options);
    if (!loaded.ok()) {
      std::fprintf(stderr, "bench_collision: %s\n", loaded.error().message.c_str());
      return 1;
    }
    cases.push_back(make_case("neuro_L" + std::to_string(level), std::move(*loaded)));
  }
  cases.push_back(make_case("tube_100k", cb::testing::make_knot_tube(1563, 32)));
  for (auto& c : cases) check_agreement(*c, perturb);
  if (check_only) return 0;
  for (auto& c : cases) register_case(*c);
  MedianReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);

  auto ms = [&](const std::string& key) {
    auto it = reporter.medians.find(key);
    return it == reporter.medians.end() ? std::nan("") : it->second;
  };
  std::printf("\nSide by side (medians; ns per closest-point query over %d points within 2 mm of the wall)\n", kPoints);
  std::printf("%-10s %9s %9s %9s %9s %9s %11s %9s %9s %9s %8s %7s %12s %7s %11s\n", "mesh", "triangles", "build_ms",
              "ours_ns", "embree_ns", "fcl_ns", "ours/embree", "fcl/ours", "cold_ns", "coh_ns", "speedup",
              "hits", "sphere350_us", "hits", "probe350_us");
  for (const auto& c : cases) {
    const std::string n = c->name + "/";
    const double ours = ms(n + "closest/ours") * 1e6 / kPoints;
    const double embree = ms(n + "closest/embree") * 1e6 / kPoints;
    const double fcl = ms(n + "closest/fcl") * 1e6 / kPoints;
    const double cold = ms(n + "walk/cold") * 1e6 / (kNodes * kSteps);
    const double coherent = ms(n + "walk/coherent") * 1e6 / (kNodes * kSteps);
    const double step_us = ms(n + "step/sphere_contacts") * 1e3 / kSteps;
    auto hit_rate = [&](const std::string& key) {
      return reporter.hit_rates.count(key) ? 100.0 * reporter.hit_rates[key] : std::nan("");
    };
    std::printf("%-10s %9zu %9.2f %9.0f %9.0f %9.0f %11.2f %9.1f %9.0f %9.0f %8.2fx %6.1f%% %12.1f %6.1f%% %11.1f\n",
                c->name.c_str(), c->mesh.triangle_count(), ms(n + "build/ours"), ours, embree, fcl, ours / embree,
                fcl / ours, cold, coherent, cold / coherent, hit_rate(n + "walk/coherent"), step_us,
                hit_rate(n + "step/sphere_contacts"), ms(n + "step/probe") * 1e3 / kSteps);
  }
  std::printf("targets: ours/embree <= 1.0, fcl/ours >= 10, build <= 50 ms at ~100k triangles, coherent speedup >= 3x\n");
  benchmark::Shutdown();
  return 0;
}
