// The pixel loop of a z-buffer rasterizer, shared by render_view and the
// texture stage's visibility buffers: which pixel centres a screen-space
// triangle covers, and their barycentric weights.
#pragma once

namespace hos::render {

// An inclusive range of pixels, x0 <= x <= x1, y0 <= y <= y1.
struct PixelRange {
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
};

// Calls visit(x, y, w0, w1, w2) for every pixel (x, y) of range whose centre
// (x + 0.5, y + 0.5) lies in the triangle a, b, c (anything with x() and y()
// in pixels), where w are the centre's barycentric weights of a, b, c (each
// >= min_weight, summing to 1) and inv_area is 1 / ((b - a) x (c - a)).
// Scalar (float or double) is the precision of the edge functions. A centre
// on an edge shared by two triangles is visited for both; the caller's depth
// test decides. A slightly negative min_weight also takes centres on an edge
// that rounding puts just outside.
template <typename Point, typename Scalar, typename Visit>
void scan_triangle(const Point& a,
                   const Point& b,
                   const Point& c,
                   Scalar inv_area,
                   const PixelRange& range,
                   Visit&& visit,
                   Scalar min_weight = Scalar(0)) {
  for (int y = range.y0; y <= range.y1; ++y) {
    const Scalar py = static_cast<Scalar>(y) + Scalar(0.5);
    for (int x = range.x0; x <= range.x1; ++x) {
      const Scalar px = static_cast<Scalar>(x) + Scalar(0.5);
      // Edge functions: signed areas of the sub-triangles opposite each corner.
      const Scalar w0 = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) * inv_area;
      const Scalar w1 = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) * inv_area;
      const Scalar w2 = Scalar(1) - w0 - w1;
      if (w0 < min_weight || w1 < min_weight || w2 < min_weight) continue;
      visit(x, y, w0, w1, w2);
    }
  }
}

}  // namespace hos::render
