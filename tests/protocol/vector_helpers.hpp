#pragma once
// Helpers over the golden vectors for the protocol tests.
#include <string>
#include <vector>

#include "cbx_vectors.h"

namespace cathbox::protocol::test {

inline std::vector<const cbx_vector*> vectors_where(bool good) {
  std::vector<const cbx_vector*> out;
  for (size_t i = 0; i < cbx_vector_count; ++i) {
    if ((cbx_vectors[i].expect == CBX_OK) == good) out.push_back(&cbx_vectors[i]);
  }
  return out;
}

}  // namespace cathbox::protocol::test
