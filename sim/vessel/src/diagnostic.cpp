#include "vessel/diagnostic.hpp"

namespace cathbox::vessel {

std::string Diagnostic::to_string() const {
  std::string out = file;
  if (line > 0) {
    out += ':';
    out += std::to_string(line);
  }
  out += ": ";
  out += message;
  return out;
}

}  // namespace cathbox::vessel
