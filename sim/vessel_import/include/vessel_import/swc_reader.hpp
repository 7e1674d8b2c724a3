#pragma once
// SWC (Cannon et al. 1998; the column layout NeuroMorpho and the INCF specification use, also
// used for vascular trees reconstructed from angiography): after optional '#' header lines, one
// sample per line,
//   id  type  x  y  z  radius  parent
// id a non-negative integer, unique; type an integer (0 undefined, 1 soma, 2 axon, ... kept as the
// segment's name); x y z radius numbers; parent the id of another sample or -1 for a root.
// '#' starts a comment anywhere; blank lines and CR LF line ends are fine. Samples may come in
// any order; parents must exist and must not form a loop.
//
// Every root, every tip and every sample with two or more children is a node; the samples from
// a node to the next node form one branch, so every branching sample becomes a junction (its
// parent's branch ends there and each child's branch starts there, with the radius of the
// child's own first sample: the branching sample's radius is the parent's).
#include <cstdint>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel_import/import_error.hpp"
#include "vessel_import/network_builder.hpp"

namespace cathbox::vessel_import {

struct SwcSample {
  std::int64_t id = 0;
  std::int64_t type = 0;
  glm::dvec3 pos{0.0};
  double radius = 0.0;
  std::int64_t parent = -1;
  int line = 0;
};

struct SwcRead {
  std::vector<SwcSample> samples;     // in file order
  std::vector<ImportError> errors;    // every problem found (at most 100), in the order found
  [[nodiscard]] bool ok() const { return errors.empty(); }
};

[[nodiscard]] SwcRead parse_swc(std::string_view text, std::string_view file);

struct SwcBranches {
  std::vector<Branch> branches;  // node ids are sample ids
  std::size_t lone_samples = 0;  // roots without children (no vessel)
};

// The branches between nodes; positions and radii multiplied by `scale_to_mm`. The samples must
// have passed parse_swc.
[[nodiscard]] SwcBranches swc_branches(const std::vector<SwcSample>& samples, double scale_to_mm);

}  // namespace cathbox::vessel_import
