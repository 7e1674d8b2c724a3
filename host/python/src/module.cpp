// The Python module `cathbox._cathbox`: a Session (python::EnvSession) and the vessel files'
// segments. Errors from bad arguments are one-line Python exceptions (ValueError for a value,
// IndexError for a tool index, RuntimeError for a failed record), never a crash.
//
// Arrays: a tool's nodes, tangents, normals and radii are numpy views of the session's own
// state (no copy, read-only, the Session kept alive as their base) that stay valid until the
// next step(); copy them (numpy.array(...)) to keep them. node_buffer(t) views the rod's own
// position array: it never moves for the session's life and shows every step's state.
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "python/device_image.hpp"
#include "python/env_session.hpp"
#include "python/route_progress.hpp"
#include "python/state_observation.hpp"
#include "python/tip_points.hpp"
#include "session/metrics.hpp"
#include "vessel/hclm.hpp"

namespace py = pybind11;
using cathbox::python::EnvSession;

namespace {

// One line from a C++ error, as a Python exception of the given type.
template <class Exception>
[[noreturn]] void raise(const std::string& what) {
  throw Exception(what);
}

class PySession {
 public:
  PySession(const std::string& case_path, const std::string& record, std::int64_t period_us, bool end_at_target,
            const std::string& who) {
    cathbox::python::EnvSessionOptions o;
    o.period_us = period_us;
    o.end_at_target = end_at_target;
    o.record_path = record;
    o.who = who;
    auto opened = EnvSession::open(case_path, o);
    if (!opened) raise<py::value_error>(opened.error().message);
    s_ = std::move(opened.value());
  }
  explicit PySession(std::unique_ptr<EnvSession> s) : s_(std::move(s)) {}

  EnvSession& s() {
    if (!s_) raise<py::value_error>("the session is closed");
    return *s_;
  }
  [[nodiscard]] const EnvSession& s() const {
    if (!s_) raise<py::value_error>("the session is closed");
    return *s_;
  }

  // speeds: (tools, 2) float64 — mm/s and rad/s per tool.
  void set_speeds(const py::object& speeds) {
    const std::size_t n = s().tool_count();
    py::array_t<double, py::array::c_style | py::array::forcecast> a;
    try {
      a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(speeds);
    } catch (const py::error_already_set&) {
      a = {};
    }
    if (!a) raise<py::value_error>("action: not an array of numbers");
    const bool flat_ok = a.ndim() == 1 && static_cast<std::size_t>(a.shape(0)) == 2 * n;
    const bool shaped_ok = a.ndim() == 2 && static_cast<std::size_t>(a.shape(0)) == n && a.shape(1) == 2;
    if (!flat_ok && !shaped_ok) {
      std::string shape = "(";
      for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
      shape += a.ndim() == 1 ? ",)" : ")";
      raise<py::value_error>("action: shape " + shape + ", expected (" + std::to_string(n) +
                             ", 2): per tool insertion mm/s and rotation rad/s");
    }
    const double* d = a.data();
    for (std::size_t t = 0; t < n; ++t) {  // check all before setting any: nothing changed on error
      if (!std::isfinite(d[2 * t]) || !std::isfinite(d[2 * t + 1])) {
        raise<py::value_error>("action: tool " + std::to_string(t) + " has a speed that is not finite (" +
                               std::to_string(d[2 * t]) + " mm/s, " + std::to_string(d[2 * t + 1]) + " rad/s)");
      }
    }
    for (std::size_t t = 0; t < n; ++t) {
      auto ok = s().set_speed(t, d[2 * t], d[2 * t + 1]);
      if (!ok) raise<py::value_error>(ok.error().message);
    }
  }

  std::int64_t step(std::int64_t ticks) {
    if (ticks < 0) raise<py::value_error>("step: ticks must be >= 0, got " + std::to_string(ticks));
    EnvSession& e = s();
    py::gil_scoped_release unlocked;
    return e.step(ticks);
  }

  const cathbox::tool::ToolSnapshot& tool(std::int64_t t) const {
    const auto& tools = s().state().tools;
    if (t < 0 || static_cast<std::size_t>(t) >= tools.size()) {
      raise<py::index_error>("tool " + std::to_string(t) + " out of range: the state has " +
                             std::to_string(tools.size()) + " tool(s)");
    }
    return tools[static_cast<std::size_t>(t)];
  }

  // The case's tool t (not a released coil).
  const cathbox::tool::Rod& rod(std::int64_t t) const {
    if (t < 0 || static_cast<std::size_t>(t) >= s().tool_count()) {
      raise<py::index_error>("tool " + std::to_string(t) + " out of range: the case has " +
                             std::to_string(s().tool_count()) + " tool(s)");
    }
    return s().session().simulator().rod(static_cast<std::size_t>(t));
  }

  // The route to the target, for the path-length reward (built on first use).
  const cathbox::python::RouteProgress& route() {
    if (!route_) route_ = cathbox::python::RouteProgress(s().scene().route_mm);
    return *route_;
  }

  std::unique_ptr<EnvSession> s_;
  std::optional<cathbox::python::RouteProgress> route_;
  std::vector<float> image_scratch_;
};

// A read-only numpy view of n x 3 doubles owned by `owner`.
py::array vec3_view(std::span<const glm::dvec3> v, py::handle owner) {
  static_assert(sizeof(glm::dvec3) == 3 * sizeof(double));
  py::array a(py::dtype::of<double>(), {static_cast<py::ssize_t>(v.size()), py::ssize_t{3}},
              {static_cast<py::ssize_t>(sizeof(glm::dvec3)), static_cast<py::ssize_t>(sizeof(double))},
              v.empty() ? nullptr : &v.data()->x, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

py::array_t<double> vec3(const glm::dvec3& p) {
  py::array_t<double> a(3);
  auto m = a.mutable_unchecked<1>();
  m(0) = p.x;
  m(1) = p.y;
  m(2) = p.z;
  return a;
}

py::dict metrics_dict(const PySession& self) {
  const EnvSession& e = self.s();
  py::dict d;
  for (const auto& m : cathbox::session::named_metrics(e.metrics())) d[py::str(m.name)] = m.value;
  d["wall_force_mN"] = e.wall_force_mN();
  d["unconverged_ticks"] = e.unconverged_ticks();
  d["unconverged_share"] = e.ticks() > 0 ? static_cast<double>(e.unconverged_ticks()) / static_cast<double>(e.ticks()) : 0.0;
  return d;
}

py::array_t<double> points_from_tip(const PySession& p, std::int64_t t, std::int64_t count, double spacing_mm) {
  if (count < 0 || count > 100'000) raise<py::value_error>("points_from_tip: count " + std::to_string(count) + " outside 0..100000");
  if (!(spacing_mm >= 0.0) || !std::isfinite(spacing_mm)) {
    raise<py::value_error>("points_from_tip: spacing_mm " + std::to_string(spacing_mm) + " is not a finite length >= 0");
  }
  std::vector<glm::dvec3> points(static_cast<std::size_t>(count));
  cathbox::python::points_from_tip(p.tool(t).positions_mm, spacing_mm, points);
  py::array_t<double> out({static_cast<py::ssize_t>(count), py::ssize_t{3}});
  auto m = out.mutable_unchecked<2>();
  for (py::ssize_t k = 0; k < count; ++k) {
    const glm::dvec3& q = points[static_cast<std::size_t>(k)];
    m(k, 0) = q.x;
    m(k, 1) = q.y;
    m(k, 2) = q.z;
  }
  return out;
}

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The "state" observation (python/state_observation.hpp): float32 (state_observation_size,).
py::array_t<float> state_observation(const PySession& p, std::int64_t count, double spacing_mm, const DoubleArray& target_mm,
                                     const DoubleArray& last_action) {
  if (count < 0 || count > 100'000) raise<py::value_error>("state_observation: count " + std::to_string(count) + " outside 0..100000");
  if (!(spacing_mm >= 0.0) || !std::isfinite(spacing_mm)) {
    raise<py::value_error>("state_observation: spacing_mm " + std::to_string(spacing_mm) + " is not a finite length >= 0");
  }
  const std::size_t tools = p.s().tool_count();
  if (target_mm.size() != 3) raise<py::value_error>("state_observation: target has " + std::to_string(target_mm.size()) + " values, expected 3 (mm)");
  if (static_cast<std::size_t>(last_action.size()) != 2 * tools) {
    raise<py::value_error>("state_observation: last_action has " + std::to_string(last_action.size()) + " values, expected " +
                           std::to_string(2 * tools) + " (tools x 2)");
  }
  const std::size_t n = cathbox::python::state_observation_size(tools, static_cast<std::size_t>(count));
  py::array_t<float> out(static_cast<py::ssize_t>(n));
  const double* t = target_mm.data();
  cathbox::python::state_observation(p.s().state(), tools, static_cast<std::size_t>(count), spacing_mm, glm::dvec3(t[0], t[1], t[2]),
                                     std::span<const double>(last_action.data(), 2 * tools), 1e4,
                                     std::span<float>(out.mutable_data(), n));
  return out;
}

py::list vessel_segments(const std::string& path) {
  const auto r = cathbox::vessel::load_hclm(path);
  if (!r.ok()) raise<py::value_error>(r.errors.front().to_string());
  py::list out;
  for (const auto& seg : r.model.segments) {
    py::dict d;
    d["id"] = seg.id;
    d["name"] = seg.name;
    d["parents"] = seg.parents;
    d["children"] = seg.children;
    py::array_t<double> pts({static_cast<py::ssize_t>(seg.points.size()), py::ssize_t{4}});
    auto m = pts.mutable_unchecked<2>();
    for (std::size_t i = 0; i < seg.points.size(); ++i) {
      const auto k = static_cast<py::ssize_t>(i);
      m(k, 0) = seg.points[i].pos_mm.x;
      m(k, 1) = seg.points[i].pos_mm.y;
      m(k, 2) = seg.points[i].pos_mm.z;
      m(k, 3) = seg.points[i].radius_mm;
    }
    d["points"] = pts;  // x, y, z, radius (mm)
    out.append(d);
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(_cathbox, mod) {
  mod.doc() = "Cathbox sessions from Python (host/python/README.md)";
  mod.def("vessel_segments", &vessel_segments, py::arg("hclm_path"),
        "The segments of an HCLM vessel file: id, name, parents, children, points (n, 4: x y z radius mm).");

  py::class_<PySession>(mod, "Session")
      .def(py::init<const std::string&, const std::string&, std::int64_t, bool, const std::string&>(),
           py::arg("case"), py::arg("record") = "", py::arg("period_us") = 1000, py::arg("end_at_target") = true,
           py::arg("who") = "python")
      .def_property_readonly("tool_count", [](const PySession& p) { return p.s().tool_count(); })
      .def_property_readonly("tool_names", [](const PySession& p) { return p.s().session().tool_names(); })
      .def_property_readonly("tool_kinds",
                             [](const PySession& p) {
                               std::vector<int> kinds;
                               for (std::size_t t = 0; t < p.s().tool_count(); ++t) {
                                 kinds.push_back(static_cast<int>(p.s().state().tools[t].kind));
                               }
                               return kinds;
                             })
      .def("set_speeds", &PySession::set_speeds, py::arg("speeds"),
           "Per tool (insertion mm/s, rotation rad/s), shape (tools, 2), from the next tick.")
      .def("step", &PySession::step, py::arg("ticks"),
           "Runs up to `ticks` ticks in virtual time (the GIL released); returns how many ran.")
      .def("clone", [](const PySession& p) {
             auto c = p.s().clone();
             if (!c) raise<py::value_error>(c.error().message);
             return PySession(std::move(c.value()));
           }, "A new session in the same state (the inputs replayed; the state hash checked).")
      .def("close", [](PySession& p) {
             if (!p.s_) return;
             auto ok = p.s_->close();
             if (!ok) raise<py::value_error>(ok.error().message);
           }, "Ends the run and finishes the record.")
      .def_property_readonly("ticks", [](const PySession& p) { return p.s().ticks(); })
      .def_property_readonly("time_s", [](const PySession& p) { return p.s().state().time_s; })
      .def_property_readonly("over", [](const PySession& p) { return p.s().over(); })
      .def_property_readonly("end_text", [](const PySession& p) { return p.s().session().end_text(); })
      .def("state_hash", [](const PySession& p) { return p.s().state_hash(); })
      .def("nodes", [](py::object self, std::int64_t t) { return vec3_view(self.cast<PySession&>().tool(t).positions_mm, self); },
           py::arg("tool"), "The tool's inserted nodes (n, 3) mm, entry to tip: a read-only view until the next step.")
      .def("tangents", [](py::object self, std::int64_t t) { return vec3_view(self.cast<PySession&>().tool(t).tangents, self); },
           py::arg("tool"))
      .def("normals", [](py::object self, std::int64_t t) { return vec3_view(self.cast<PySession&>().tool(t).normals, self); },
           py::arg("tool"))
      .def("node_buffer", [](py::object self, std::int64_t t) { return vec3_view(self.cast<PySession&>().rod(t).positions(), self); },
           py::arg("tool"),
           "The simulator's own node positions of the tool (node_total, 3) mm, tip last, every node (those not "
           "inserted lie on the entry line outside the body): a read-only view of the rod's buffer, no copy; "
           "it shows each step's state and lives as long as the view (the Session is its base).")
      .def("tip", [](const PySession& p, std::int64_t t) {
             const auto& tip = p.tool(t).tip;
             return py::make_tuple(vec3(tip.position_mm), vec3(tip.direction), vec3(tip.normal));
           }, py::arg("tool"), "(position mm, unit direction, unit bend) of the tool's tip.")
      .def("points_from_tip", &points_from_tip, py::arg("tool"), py::arg("count"), py::arg("spacing_mm"),
           "(count, 3) mm: points along the tool every spacing_mm back from its tip (the first the tip; past the "
           "entry the first node repeated). A new array (python/tip_points.hpp).")
      .def("state_observation", &state_observation, py::arg("count"), py::arg("spacing_mm"), py::arg("target"),
           py::arg("last_action"),
           "The environments' state observation, float32: per tool points_from_tip(count, spacing_mm), the tip's "
           "direction, insertion mm, rotation rad; the target (3) mm; the last action (tools, 2); clipped to +-1e4.")
      .def("insertion_mm", [](const PySession& p, std::int64_t t) { return p.tool(t).insertion_mm; }, py::arg("tool"))
      .def("rotation_rad", [](const PySession& p, std::int64_t t) { return p.tool(t).rotation_rad; }, py::arg("tool"))
      .def("hand_force_mN", [](const PySession& p, std::int64_t t) { return p.tool(t).hand_force_mN; }, py::arg("tool"))
      .def("tip_segment", [](const PySession& p, std::int64_t t) { return p.tool(t).tip_segment; }, py::arg("tool"))
      .def("contacts", [](const PySession& p, std::int64_t t) {
             const auto& c = p.tool(t).contacts;
             py::array_t<double> a({static_cast<py::ssize_t>(c.size()), py::ssize_t{5}});
             auto m = a.mutable_unchecked<2>();
             for (std::size_t i = 0; i < c.size(); ++i) {
               const auto k = static_cast<py::ssize_t>(i);
               m(k, 0) = c[i].node;
               m(k, 1) = c[i].point_mm.x;
               m(k, 2) = c[i].point_mm.y;
               m(k, 3) = c[i].point_mm.z;
               m(k, 4) = c[i].normal_force_mN;
             }
             return a;
           }, py::arg("tool"), "The tool's wall contacts (n, 5): node, x, y, z mm, normal force mN.")
      .def("metrics", &metrics_dict, "The session's metrics by name, plus wall_force_mN and the unconverged share.")
      .def_property_readonly("target", [](const PySession& p) -> py::object {
             const auto& t = p.s().scene().target_mm;
             if (!t) return py::none();
             return vec3(glm::dvec3(*t));
           })
      .def_property_readonly("target_radius_mm", [](const PySession& p) { return p.s().scene().target_radius_mm; })
      .def_property_readonly("route", [](const PySession& p) {
             const auto& r = p.s().scene().route_mm;
             py::array_t<double> a({static_cast<py::ssize_t>(r.size()), py::ssize_t{3}});
             auto m = a.mutable_unchecked<2>();
             for (std::size_t i = 0; i < r.size(); ++i) {
               for (int j = 0; j < 3; ++j) m(static_cast<py::ssize_t>(i), j) = r[i][j];
             }
             return a;
           }, "The centreline from the entry to the target (n, 3) mm.")
      .def("route_remaining_mm", [](PySession& p, std::int64_t t) { return p.route().remaining_mm(p.tool(t).tip.position_mm); },
           py::arg("tool"),
           "The route length left from the tool's tip to the target: past the tip's closest point on the route, "
           "plus the tip's distance off it (mm; python/route_progress.hpp).")
      .def_property_readonly("route_length_mm", [](const PySession& p) { return p.s().scene().route_length_mm; })
      .def("set_c_arm", [](PySession& p, double lao_deg, double cranial_deg, double fov_mm) {
             cathbox::flow::CArmPose pose = p.s().c_arm().pose();
             pose.lao_deg = lao_deg;
             pose.cranial_deg = cranial_deg;
             pose.fov_mm = fov_mm;
             auto ok = p.s().set_c_arm(pose);
             if (!ok) raise<py::value_error>("C-arm: " + ok.error().message);
           }, py::arg("lao_deg") = 0.0, py::arg("cranial_deg") = 0.0, py::arg("fov_mm") = 220.0)
      .def("session_capsule", [](PySession& p) {
             return py::capsule(static_cast<void*>(&p.s().session()), "cathbox.session");
           }, "The host/session Session for host/app's offscreen fluoroscopy (cathbox._fluoro); valid while this Session lives.")
      .def("press_pedal", [](PySession& p) { p.s().press_pedal(); },
           "Holds the fluoroscopy foot pedal down from the next tick (pulses at the unit's rate; recorded).")
      .def_property_readonly("c_arm_pose", [](const PySession& p) {
             const auto& pose = p.s().c_arm().pose();
             return py::make_tuple(pose.lao_deg, pose.cranial_deg, pose.fov_mm, pose.isocenter_mm.x, pose.isocenter_mm.y,
                                   pose.isocenter_mm.z);
           }, "(lao_deg, cranial_deg, fov_mm, isocentre x, y, z mm) of the session's C-arm.")
      .def("project", [](const PySession& p, const py::array_t<double, py::array::c_style | py::array::forcecast>& pts) {
             if (pts.ndim() != 2 || pts.shape(1) != 3) raise<py::value_error>("project: points must have shape (n, 3)");
             py::array_t<double> out({pts.shape(0), py::ssize_t{2}});
             auto in = pts.unchecked<2>();
             auto m = out.mutable_unchecked<2>();
             const auto& arm = p.s().c_arm();
             for (py::ssize_t i = 0; i < pts.shape(0); ++i) {
               const glm::dvec2 q = arm.project_mm({in(i, 0), in(i, 1), in(i, 2)});
               m(i, 0) = q.x;
               m(i, 1) = q.y;
             }
             return out;
           }, py::arg("points"), "Points (n, 3) mm onto the detector through the C-arm: (n, 2) mm, x right, y up.")
      .def("image", [](PySession& p, int width, int height) {
             if (width < 8 || height < 8 || width > 2048 || height > 2048) {
               raise<py::value_error>("image: size " + std::to_string(width) + "x" + std::to_string(height) +
                                      " outside 8..2048");
             }
             py::array_t<std::uint8_t> out({static_cast<py::ssize_t>(height), static_cast<py::ssize_t>(width)});
             std::span<std::uint8_t> bytes(out.mutable_data(), static_cast<std::size_t>(width * height));
             EnvSession& e = p.s();
             {
               py::gil_scoped_release unlocked;
               cathbox::python::render_device_image(e.state(), e.c_arm(), width, height, bytes, p.image_scratch_);
             }
             return out;
           }, py::arg("width") = 128, py::arg("height") = 128,
           "The tools as a fluoroscopic image (height, width) uint8, through the C-arm (device_image.hpp).");
}
