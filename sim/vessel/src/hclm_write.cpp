// The HCLM writer: a model as text in the thesis' format (Appendix A), doubles written to round
// trip.
#include <fstream>
#include <string>

#include "base/float_chars.hpp"
#include "vessel/hclm.hpp"

namespace cathbox::vessel {
namespace {

std::string format_double(double value) {
  char buf[64];
  const auto [ptr, ec] = base::double_chars(buf, buf + sizeof buf, value);
  if (ec != std::errc()) return "nan";
  return std::string(buf, ptr);
}

}  // namespace

std::string write_hclm(const VesselModel& model) {
  std::string out;
  out.reserve(64 + model.point_count() * 64);
  const auto write_list = [&](char label, const std::vector<std::int32_t>& ids) {
    out += label;
    out += ' ';
    out += std::to_string(ids.size());
    for (std::int32_t id : ids) {
      out += ' ';
      out += std::to_string(id);
    }
    out += '\n';
  };
  out += "s " + std::to_string(model.segments.size()) + "\n";
  for (const Segment& s : model.segments) {
    out += "\ng " + std::to_string(s.id) + "\n";
    out += "l " + s.name + "\n";
    out += "f " + format_double(s.flow) + "\n";
    write_list('p', s.parents);
    write_list('c', s.children);
    out += "n " + std::to_string(s.points.size()) + "\n";
    for (const CenterlinePoint& p : s.points) {
      out += "v " + format_double(p.pos_mm.x) + ' ' + format_double(p.pos_mm.y) + ' ' + format_double(p.pos_mm.z) +
             ' ' + format_double(p.radius_mm) + '\n';
    }
  }
  return out;
}

std::string save_hclm(const VesselModel& model, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return "cannot open " + path + " for writing";
  out << write_hclm(model);
  out.flush();
  if (!out) return "cannot write " + path;
  return {};
}

}  // namespace cathbox::vessel
