#include "session/hand.hpp"

#include "session/control.hpp"

namespace cathbox::session {

const char* hand_kind_name(HandKind kind) {
  switch (kind) {
    case HandKind::kBox: return "box";
    case HandKind::kKeyboard: return "keyboard";
    case HandKind::kScripted: return "scripted";
    case HandKind::kActionScript: return "action script";
    case HandKind::kReplay: return "replay";
    case HandKind::kProgram: return "program";
  }
  return "unknown";
}

std::optional<DeviceRecord> Hand::device() const { return std::nullopt; }
void Hand::controls(std::int64_t, ControlSink&) {}
void Hand::hold(std::size_t, const ToolCommand&) {}
void Hand::restart(std::size_t, const ToolCommand&) {}
void Hand::feel(const HandFeedback&) {}
void Hand::release() {}
bool Hand::finished() const { return false; }
std::string Hand::finish_reason() const { return {}; }

}  // namespace cathbox::session
