#include "app/phantom_projections.hpp"

#include <chrono>
#include <utility>

namespace cathbox::app {
namespace {

template <class P>
bool ready(const P& p) {
  return p.path.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

}  // namespace

PhantomProjections::Projection PhantomProjections::launch(const flow::HeadPhantom& phantom, const flow::CArm& carm,
                                                          std::uint64_t key, Size size) {
  return Projection{key, std::async(std::launch::async, [phantom, carm, size] { return phantom.project(carm, size.width, size.height); })};
}

void PhantomProjections::adopt(std::vector<float> path, const flow::HeadPhantom& phantom, const flow::CArm& carm,
                               const Request& request) {
  // The projection for this key replaces the current one, which is kept as the spare. With
  // background projection the other readout's at this pose follows on a worker (a subtraction
  // run soon after the fluoroscopy that placed the C-arm then finds its phantom ready).
  spare_path_ = std::move(path_);
  spare_key_ = key_;
  path_ = std::move(path);
  key_ = request.key;
  if (background_ && request.other_key != request.key && request.other_key != spare_key_ && !other_pending_) {
    other_pending_ = launch(phantom, carm, request.other_key, request.other);
  }
}

PhantomProjections::Outcome PhantomProjections::use(const flow::HeadPhantom& phantom, const flow::CArm& carm,
                                                    const Request& request, bool can_hold, bool& projected) {
  projected = false;
  const std::uint64_t key = request.key;
  // The other readout's projection, once done, is the spare (unless it is the current one).
  if (other_pending_ && ready(*other_pending_)) {
    std::vector<float> path = other_pending_->path.get();
    if (other_pending_->key != key_) {
      spare_path_ = std::move(path);
      spare_key_ = other_pending_->key;
    }
    other_pending_.reset();
  }
  if (key == key_) return Outcome::kSame;
  if (key == spare_key_) {
    // The same pose at the other readout (a subtraction run after binned fluoroscopy, and back):
    // kept, not projected again.
    std::swap(path_, spare_path_);
    std::swap(key_, spare_key_);
    return Outcome::kChanged;
  }
  // A last image to show meanwhile (of any size: the copy to the window scales it): project on
  // a worker thread.
  const bool hold = background_ && can_hold;
  if (pending_ && pending_->key != key && ready(*pending_)) pending_.reset();  // a pose passed by: dropped
  if (!pending_ && other_pending_ && other_pending_->key == key) {
    pending_ = std::move(other_pending_);  // the other readout's, under way: waited for, not started again
    other_pending_.reset();
  }
  if (pending_ && pending_->key == key && (ready(*pending_) || !hold)) {
    adopt(pending_->path.get(), phantom, carm, request);
    pending_.reset();
  } else if (hold) {
    // One projection at a time: a newer pose starts when the one under way is done.
    if (!pending_) pending_ = launch(phantom, carm, key, request.size);
    return Outcome::kWaiting;
  } else {
    pending_.reset();  // waits for a projection under way
    adopt(phantom.project(carm, request.size.width, request.size.height), phantom, carm, request);
  }
  projected = true;
  return Outcome::kChanged;
}

}  // namespace cathbox::app
