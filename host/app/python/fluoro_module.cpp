// The Python module `cathbox._fluoro`: the trainer's fluoroscopic view of a cathbox.Session,
// rendered offscreen (app::OffscreenFluoro). The session comes as the capsule
// cathbox.Session.session_capsule() gives; the Python caller keeps the Session alive as long
// as the View (cathbox/fluoroscopy.py does). Errors are one-line RuntimeError / ValueError.
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "app/offscreen_fluoro.hpp"

namespace py = pybind11;
using cathbox::app::OffscreenFluoro;

namespace {

cathbox::session::Session& session_of(const py::capsule& capsule) {
  if (std::string(capsule.name() ? capsule.name() : "") != "cathbox.session") {
    throw py::value_error("fluoroscopy: not a cathbox session capsule (use Session.session_capsule())");
  }
  return *capsule.get_pointer<cathbox::session::Session>();
}

class View {
 public:
  View(const py::capsule& session, int width, int height) {
    cathbox::base::Result<std::unique_ptr<OffscreenFluoro>> made = OffscreenFluoro::create(session_of(session), width, height);
    if (!made) throw std::runtime_error(made.error().message);
    view_ = std::move(*made);
  }
  py::array_t<std::uint8_t> render(const py::capsule& session, double lao_deg, double cranial_deg, double fov_mm,
                                   double iso_x, double iso_y, double iso_z) {
    cathbox::flow::CArmPose pose;
    pose.lao_deg = lao_deg;
    pose.cranial_deg = cranial_deg;
    pose.fov_mm = fov_mm;
    pose.isocenter_mm = {iso_x, iso_y, iso_z};
    if (const std::string why = cathbox::flow::check_pose(pose); !why.empty()) throw py::value_error("C-arm: " + why);
    py::array_t<std::uint8_t> out({static_cast<py::ssize_t>(view_->height()), static_cast<py::ssize_t>(view_->width())});
    const std::string error = view_->render(session_of(session), pose,
                                            std::span<std::uint8_t>(out.mutable_data(), static_cast<std::size_t>(out.size())));
    if (!error.empty()) throw std::runtime_error("fluoroscopy: " + error);
    return out;
  }

 private:
  std::unique_ptr<OffscreenFluoro> view_;
};

}  // namespace

PYBIND11_MODULE(_fluoro, mod) {
  mod.doc() = "The trainer's fluoroscopic view of a cathbox.Session, offscreen (host/app/python)";
  py::class_<View>(mod, "View")
      .def(py::init<const py::capsule&, int, int>(), py::arg("session"), py::arg("width"), py::arg("height"))
      .def("render", &View::render, py::arg("session"), py::arg("lao_deg"), py::arg("cranial_deg"), py::arg("fov_mm"),
           py::arg("iso_x"), py::arg("iso_y"), py::arg("iso_z"),
           "The image (height, width) uint8 of the session's newest state through the C-arm pose.");
}
