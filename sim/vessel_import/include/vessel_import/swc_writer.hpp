#pragma once
// A vessel tree as SWC text (the reverse of swc_reader.hpp): one sample per centreline point, in
// millimetres, type 0; a junction is one sample, the parent's last point and its children's first.
// SWC holds trees only: a segment with more than one parent, or a cycle, is refused.
#include <string>

#include "vessel/vessel_model.hpp"

namespace cathbox::vessel_import {

struct SwcWrite {
  std::string text;
  std::string error;  // empty on success
  [[nodiscard]] bool ok() const { return error.empty(); }
};

[[nodiscard]] SwcWrite write_swc(const vessel::VesselModel& model, const std::string& comment = "");

}  // namespace cathbox::vessel_import
