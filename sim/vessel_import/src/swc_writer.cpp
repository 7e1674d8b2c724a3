#include "vessel_import/swc_writer.hpp"

#include <charconv>
#include <deque>
#include <unordered_map>

namespace cathbox::vessel_import {
namespace {

void number(std::string& out, double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  if (ec == std::errc()) out.append(buf, end);
}

}  // namespace

SwcWrite write_swc(const vessel::VesselModel& model, const std::string& comment) {
  SwcWrite out;
  std::unordered_map<std::int32_t, std::size_t> index;
  for (std::size_t i = 0; i < model.segments.size(); ++i) index.emplace(model.segments[i].id, i);
  for (const vessel::Segment& s : model.segments) {
    if (s.parents.size() > 1) {
      out.error = "segment " + std::to_string(s.id) + " has " + std::to_string(s.parents.size()) +
                  " parents: SWC holds trees only";
      return out;
    }
  }
  out.text = "# " + (comment.empty() ? std::string("cathbox vessel tree") : comment) +
             "\n# id type x y z radius parent (millimetres)\n";
  std::vector<std::int64_t> last_sample(model.segments.size(), -1);  // each segment's last point
  std::vector<char> written(model.segments.size(), 0);
  std::int64_t next = 0;
  const auto sample = [&](const vessel::CenterlinePoint& p, std::int64_t parent) {
    ++next;
    out.text += std::to_string(next) + " 0 ";
    number(out.text, p.pos_mm.x);
    out.text += ' ';
    number(out.text, p.pos_mm.y);
    out.text += ' ';
    number(out.text, p.pos_mm.z);
    out.text += ' ';
    number(out.text, p.radius_mm);
    out.text += ' ' + std::to_string(parent) + '\n';
    return next;
  };
  // Roots first, then children after their parent (breadth first).
  std::deque<std::size_t> queue;
  for (std::size_t i = 0; i < model.segments.size(); ++i) {
    if (model.segments[i].parents.empty()) queue.push_back(i);
  }
  std::size_t done = 0;
  while (!queue.empty()) {
    const std::size_t i = queue.front();
    queue.pop_front();
    if (written[i]) continue;
    written[i] = 1;
    ++done;
    const vessel::Segment& s = model.segments[i];
    std::int64_t parent = -1;
    std::size_t first = 0;
    if (!s.parents.empty()) {
      parent = last_sample[index.at(s.parents.front())];  // the junction sample
      first = 1;
    }
    for (std::size_t k = first; k < s.points.size(); ++k) parent = sample(s.points[k], parent);
    last_sample[i] = parent;
    for (std::int32_t child : s.children) {
      const auto it = index.find(child);
      if (it != index.end() && !written[it->second]) queue.push_back(it->second);
    }
  }
  if (done != model.segments.size()) {
    out.error = "the network has a cycle: SWC holds trees only";
    out.text.clear();
  }
  return out;
}

}  // namespace cathbox::vessel_import
