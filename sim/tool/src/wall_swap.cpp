#include "tool/wall_swap.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <utility>

#include "collision/obb_tree.hpp"
#include "tool/mesh_wall.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::tool {

namespace {

using WallResult = base::Result<std::unique_ptr<WallModel>>;

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Builds one wall, timing it in wall and in the building thread's CPU seconds.
WallResult timed_build(const WallBuilder& builder, const vessel::VesselModel& model, double& seconds,
                       double& cpu_seconds) {
  const double c0 = thread_cpu_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  WallResult wall = builder(model);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  cpu_seconds = thread_cpu_seconds() - c0;
  return wall;
}

}  // namespace

namespace {

// The wall on `surface` (its mesh), holding `model` for the renderers and the lumen reads.
WallResult mesh_wall_on(const vessel::VesselModel& model, vessel::VesselSurface surface, collision::TreeCache* cache) {
  if (!surface.ok()) return base::Error{"widened vessel: " + surface.error};
  collision::TreeBuild tree = cache != nullptr ? collision::ObbTree::build(surface.mesh, {}, *cache)
                                               : collision::ObbTree::build(surface.mesh);
  if (!tree) return base::Error{"widened vessel surface rejected by the collision tree: " + tree.error().message};
  // The tree keeps its own copy of the mesh: the surface moves on to the renderers.
  auto drawn = std::make_shared<WallSurface>(WallSurface{model, std::move(surface.mesh)});
  return WallResult(std::make_unique<MeshWall>(std::move(*tree), MeshWall::kDefaultHintSlots, std::move(drawn)));
}

}  // namespace

WallResult build_mesh_wall(const vessel::VesselModel& model, collision::TreeCache* cache) {
  return mesh_wall_on(model, vessel::build_vessel_surface(model), cache);
}

WallResult build_mesh_wall(const vessel::VesselModel& model, vessel::SurfaceMesh made) {
  return mesh_wall_on(model, vessel::build_vessel_surface(model, std::move(made)), nullptr);
}

WallBuilder cached_mesh_wall_builder() {
  auto cache = std::make_shared<collision::TreeCache>();
  return [cache](const vessel::VesselModel& model) { return build_mesh_wall(model, cache.get()); };
}

WallSwap::WallSwap(std::unique_ptr<WallModel> initial, WallBuilder builder, Mode mode, std::int64_t latency_ticks)
    : current_(std::move(initial)), builder_(std::move(builder)), mode_(mode), latency_(std::max<std::int64_t>(0, latency_ticks)) {
  retired_.reserve(4);
  surface_.store(current_->surface());
}

std::shared_ptr<const WallSurface> WallSwap::surface() const { return surface_.load(std::memory_order_acquire); }

void WallSwap::set_mode(Mode mode) {
  if (!due_tick_) mode_ = mode;
}

WallSwap::~WallSwap() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

bool WallSwap::request(const vessel::VesselModel& model, std::int64_t now) {
  if (due_tick_) return false;
  ++requests_;
  due_tick_ = now + latency_;
  if (mode_ == Mode::kSynchronous) {
    double seconds = 0.0, cpu_seconds = 0.0;
    done_.emplace(timed_build(builder_, model, seconds, cpu_seconds));
    build_seconds_.push_back(seconds);
    build_cpu_seconds_.push_back(cpu_seconds);
    return true;
  }
  if (!worker_.joinable()) worker_ = std::thread([this] { work(); });
  {
    const std::lock_guard lock(mutex_);
    job_model_ = model;
    has_job_ = true;
    busy_ = true;
  }
  wake_.notify_one();
  return true;
}

void WallSwap::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || has_job_ || !retired_.empty(); });
    std::vector<std::unique_ptr<WallModel>> old;
    old.swap(retired_);
    const bool job = has_job_;
    if (job) std::swap(job_model_, work_model_);
    has_job_ = false;
    if (!job && stop_ && old.empty()) return;
    lock.unlock();
    old.clear();  // the replaced walls die here, off the haptic thread
    double seconds = 0.0, cpu_seconds = 0.0;
    std::optional<WallResult> built;
    if (job) built.emplace(timed_build(builder_, work_model_, seconds, cpu_seconds));
    lock.lock();
    if (built) {
      done_ = std::move(built);
      build_seconds_.push_back(seconds);
      build_cpu_seconds_.push_back(cpu_seconds);
      busy_ = false;
      idle_.notify_all();
    }
    retired_.reserve(4);
  }
}

void WallSwap::retire(std::unique_ptr<WallModel> old) {
  if (!worker_.joinable()) return;  // synchronous so far: `old` is destroyed here
  {
    const std::lock_guard lock(mutex_);
    retired_.push_back(std::move(old));
  }
  wake_.notify_one();
}

void WallSwap::WaitTally::add(double seconds) {
  recent[count % kRecent] = seconds;
  ++count;
  total_seconds += seconds;
  max_seconds = std::max(max_seconds, seconds);
}

std::vector<double> WallSwap::WaitTally::recent_seconds() const {
  const std::uint64_t kept = std::min<std::uint64_t>(count, kRecent);
  std::vector<double> out;
  out.reserve(kept);
  for (std::uint64_t k = count - kept; k < count; ++k) out.push_back(recent[k % kRecent]);
  return out;
}

bool WallSwap::poll(Simulator& sim, std::int64_t now) {
  if (!due_tick_ || now < *due_tick_) return false;
  std::optional<WallResult> built;
  {
    std::unique_lock lock(mutex_);
    if (!done_) {  // only with the worker: the build is late, this tick waits for it
      if (wait_hook_) {
        lock.unlock();
        wait_hook_();
        lock.lock();
      }
      const auto t0 = std::chrono::steady_clock::now();
      idle_.wait(lock, [&] { return done_.has_value(); });
      wait_tally_.add(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    built.swap(done_);
  }
  due_tick_.reset();
  if (!built->ok()) {
    ++failures_;
    last_error_ = built->error().message;
    return false;
  }
  std::unique_ptr<WallModel> next = std::move(built->value());
  sim.swap_wall(*next);
  // Published before the old wall is retired: the old surface's last owner is then the retired
  // wall (destroyed by the worker) or a renderer, never this thread.
  surface_.store(next->surface(), std::memory_order_release);
  std::unique_ptr<WallModel> old = std::exchange(current_, std::move(next));
  ++swaps_;
  generation_.store(swaps_, std::memory_order_release);
  retire(std::move(old));
  return true;
}

void WallSwap::drain() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [&] { return !busy_; });
}

std::vector<double> WallSwap::build_seconds() const {
  const std::lock_guard lock(mutex_);
  return build_seconds_;
}

std::vector<double> WallSwap::build_cpu_seconds() const {
  const std::lock_guard lock(mutex_);
  return build_cpu_seconds_;
}

}  // namespace cathbox::tool
