#pragma once
// The trainee page's hand: the keyboard hand (the page writes the speeds, from the keys or from
// the box's servo), keeping the held tool's newest local force law from the session's feedback,
// which the page's box path turns into the box's command (wasm/browser_box_law.hpp), as BoxHand
// does natively. Everything else is the keyboard hand's, so the record is the same.
#include <memory>
#include <string>

#include "session/hand.hpp"

namespace cathbox::wasm {

class LawTapHand final : public session::Hand {
 public:
  explicit LawTapHand(std::unique_ptr<session::Hand> inner) : inner_(std::move(inner)) {}

  [[nodiscard]] session::HandKind kind() const override { return inner_->kind(); }
  [[nodiscard]] std::string describe() const override { return inner_->describe(); }
  void hold(std::size_t tool, const session::ToolCommand& at) override { inner_->hold(tool, at); }
  void restart(std::size_t tool, const session::ToolCommand& at) override { inner_->restart(tool, at); }
  void read(std::int64_t tick, session::TickInput& input) override { inner_->read(tick, input); }
  void feel(const session::HandFeedback& feedback) override {
    if (feedback.tick >= 0) law_ = feedback.law;
    inner_->feel(feedback);
  }

  // The held tool's local force law after the newest tick, in the session's frame.
  [[nodiscard]] const tool::ForceLaw& law() const { return law_; }

 private:
  std::unique_ptr<session::Hand> inner_;
  tool::ForceLaw law_;
};

}  // namespace cathbox::wasm
