// Fuzzes what the VTK importer does after VTK: line cells and point arrays (decoded from the
// bytes: point count, points as signed bytes in mm, radii, cells as point ids that may be out of
// range, CenterlineIds/TractIds) to polylines, then the network builder, the radius filter and
// validation. Overlapping, touching and repeated polylines come out of small coordinates often.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_check.hpp"
#include "vessel/radius_filter.hpp"
#include "vessel_import/vtk_centerlines.hpp"

namespace {

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  [[nodiscard]] bool empty() const { return at_ >= size_; }
  uint8_t next() { return at_ < size_ ? data_[at_++] : 0; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t at_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace cathbox::vessel_import;
  Bytes in(data, size);
  PolylineArrays a;
  a.radius_array = "MaximumInscribedSphereRadius";
  const int points = in.next() % 64;
  for (int i = 0; i < points; ++i) {
    const auto coord = [&] { return 0.5 * static_cast<int8_t>(in.next()); };
    const double x = coord(), y = coord(), z = coord();
    a.points.emplace_back(x, y, z);
    a.radius.push_back(0.05 * in.next());  // 0 .. 12.75 mm, zero included
  }
  if (in.next() == 0xee && !a.radius.empty()) a.radius.pop_back();  // sizes disagree
  const int lines = in.next() % 12;
  for (int c = 0; c < lines && !in.empty(); ++c) {
    std::vector<std::int64_t> cell;
    const int length = in.next() % 24;
    for (int k = 0; k < length; ++k) cell.push_back(static_cast<std::int64_t>(in.next()) - 2);  // -2 .. 253
    a.lines.push_back(std::move(cell));
  }
  if (in.next() % 2 == 1) {
    for (std::size_t c = 0; c < a.lines.size(); ++c) {
      a.centerline_ids.push_back(in.next() % 4);
      a.tract_ids.push_back(in.next() % 5);
    }
    if (in.next() == 0xee && !a.tract_ids.empty()) a.tract_ids.pop_back();
  }
  const PolylinesRead read = centerline_polylines(a, "fuzz.vtp", 1.0);
  ImportResult result;
  if (!read.ok()) {
    result.errors = read.errors;
    fuzz::check(result);
    return 0;
  }
  const NetworkBuild built = build_network(read.polylines);
  if (!built.ok()) {
    if (built.error.empty()) std::abort();
    return 0;
  }
  result.model = built.model;
  result.network = built.stats;
  result.filter = cathbox::vessel::filter_radii(result.model);
  result.filtered = true;
  if (result.filter.unusable_segments > 0) return 0;  // the importer refuses those
  fuzz::check(result);
  return 0;
}
