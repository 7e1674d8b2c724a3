// The scene targets' bookkeeping: rectangles of GL pixels and 64 x 64 cells (llvmpipe's tiles)
// marking where a target was drawn or may hold anything but zero.
#include <algorithm>

#include "app/fluoro_renderer.hpp"

namespace cathbox::app {

FluoroRenderer::Rect FluoroRenderer::unite(const Rect& a, const Rect& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

void FluoroRenderer::CellMask::reset(int w, int h, bool value) {
  width = w;
  height = h;
  on.assign(static_cast<std::size_t>(((w + kCell - 1) / kCell) * ((h + kCell - 1) / kCell)), value ? 1 : 0);
}

void FluoroRenderer::CellMask::mark(const Rect& r) {
  if (r.empty()) return;
  const int columns = (width + kCell - 1) / kCell;
  for (int cy = r.y0 / kCell; cy <= (r.y1 - 1) / kCell; ++cy) {
    for (int cx = r.x0 / kCell; cx <= (r.x1 - 1) / kCell; ++cx) on[static_cast<std::size_t>(cy * columns + cx)] = 1;
  }
}

void FluoroRenderer::CellMask::unite(const CellMask& other) {
  for (std::size_t i = 0; i < on.size() && i < other.on.size(); ++i) on[i] = static_cast<unsigned char>(on[i] | other.on[i]);
}

FluoroRenderer::Rect FluoroRenderer::CellMask::bounds() const {
  Rect b;
  for (const Rect& r : runs(true)) b = FluoroRenderer::unite(b, r);
  return b;
}

std::vector<FluoroRenderer::Rect> FluoroRenderer::CellMask::runs(bool value) const {
  const int columns = (width + kCell - 1) / kCell;
  const int rows = (height + kCell - 1) / kCell;
  std::vector<Rect> out;
  for (int cy = 0; cy < rows; ++cy) {
    for (int cx = 0; cx < columns;) {
      if ((on[static_cast<std::size_t>(cy * columns + cx)] != 0) != value) {
        ++cx;
        continue;
      }
      const int x0 = cx;
      while (cx < columns && (on[static_cast<std::size_t>(cy * columns + cx)] != 0) == value) ++cx;
      const Rect r{x0 * kCell, cy * kCell, std::min(cx * kCell, width), std::min((cy + 1) * kCell, height)};
      // A rectangle of the same columns ending at this row: grow it instead.
      const auto below = std::find_if(out.begin(), out.end(), [&](const Rect& o) { return o.x0 == r.x0 && o.x1 == r.x1 && o.y1 == r.y0; });
      if (below != out.end()) {
        below->y1 = r.y1;
      } else {
        out.push_back(r);
      }
    }
  }
  return out;
}

}  // namespace cathbox::app
