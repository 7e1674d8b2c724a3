#pragma once
// A fluoroscopic image of the tools drawn on the CPU, for the environments' image observation:
// every tool is a tube along its inserted nodes, projected through the C-arm (flow::CArm:
// perspective from the focal spot, magnification SID / depth), and darkens the image by
// exp(-mu x chord), the chord of the tube at that pixel on the detector's scale; guidewires
// (metal) attenuate more than catheters (polymer). No vessels (no contrast), no noise, no
// anatomy: what the agent sees is the devices on a flat field, as stEVE's image observation.
// The trainer's fluoroscopy (host/app, GL: contrast, roadmap, noise) is not used: DESIGN.md's
// table keeps host/python off GL, and this needs no display.
#include <cstdint>
#include <span>
#include <vector>

#include "flow/c_arm.hpp"
#include "tool/snapshot.hpp"

namespace cathbox::python {

struct DeviceImageSettings {
  float field = 0.85F;               // the unattenuated grey level (0..1)
  double guidewire_mu_per_mm = 2.5;  // attenuation per mm of chord (the image's scale)
  double catheter_mu_per_mm = 0.6;
};

// `out` holds width x height bytes, row by row from the top (0 black .. 255 white). `scratch`
// is reused between calls (no allocation once sized).
void render_device_image(const tool::Snapshot& state, const flow::CArm& c_arm, int width, int height,
                         std::span<std::uint8_t> out, std::vector<float>& scratch,
                         const DeviceImageSettings& settings = {});

}  // namespace cathbox::python
