#pragma once
// What contrast_transport.cpp and contrast_transport_step.cpp share. Private to sim/flow.

namespace cathbox::flow::contrast_detail {

inline constexpr double kFlowNoise = 1e-9;        // flows below this share of the largest are zero

}  // namespace cathbox::flow::contrast_detail
