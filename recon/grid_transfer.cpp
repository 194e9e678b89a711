#include "recon/grid_transfer.h"

#include <algorithm>

namespace hos::recon {

namespace {

// Fine node j lies at coarse coordinate (j - 1) / 2: on a coarse node when j
// is odd, halfway between two when j is even.
struct AxisWeights {
  int c0, c1;
  double w0, w1;
};
AxisWeights axis_weights(int j) {
  if (j % 2 == 1) return {(j - 1) / 2, (j - 1) / 2, 1.0, 0.0};
  return {j / 2 - 1, j / 2, 0.5, 0.5};
}

}  // namespace

template <typename T>
void restrict_to_coarse(const GridGeometry& fine,
                        const ActiveNodes& fine_nodes,
                        const T* r,
                        const GridGeometry& /*coarse*/,
                        const ActiveNodes& coarse_active,
                        T* rc) {
  const int nx = fine.dims.x();
#pragma omp parallel if (worth_threads(8 * coarse_active.count()))
  {
    // The 9 fine rows around a coarse row, fine nodes 2 begin <= i <= 2 end.
    std::vector<T> lines(9 * static_cast<std::size_t>(nx + 1));
#pragma omp for schedule(static)
    for (std::int64_t s = 0; s < static_cast<std::int64_t>(coarse_active.spans().size()); ++s) {
      const NodeSpan& span = coarse_active.spans()[s];
      const int lo = 2 * span.begin, hi = 2 * span.end + 1;
      for (int q = 0; q < 9; ++q) {
        fine_nodes.gather_row(r, 2 * span.j + q % 3, 2 * span.k + q / 3, lo, hi,
                              lines.data() + q * std::size_t(nx + 1));
      }
      for (int i = span.begin; i < span.end; ++i) {
        // Coarse node (i, j, k) sits on fine node (2i+1, 2j+1, 2k+1); its 27
        // fine neighbours are inside the fine grid by construction.
        double sum = 0.0;
        for (int q = 0; q < 9; ++q) {
          const T* p = lines.data() + q * std::size_t(nx + 1) + (2 * i + 1 - lo);
          const double w = (q % 3 == 1 ? 1.0 : 0.5) * (q / 3 == 1 ? 1.0 : 0.5);
          sum += w * (0.5 * p[-1] + p[0] + 0.5 * p[1]);
        }
        rc[span.first + (i - span.begin)] = static_cast<T>(sum / 8.0);
      }
    }
  }
}

namespace {

// prolongate_add on the fine nodes of these spans.
template <typename T>
void prolongate_add_spans(const GridGeometry& coarse,
                          const ActiveNodes& coarse_nodes,
                          const T* ec,
                          const std::vector<NodeSpan>& spans,
                          std::int64_t count,
                          T* x) {
  const Eigen::Vector3i dc = coarse.dims;
#pragma omp parallel if (worth_threads(count))
  {
    // The coarse values interpolated in y and z for one fine row, padded by a
    // zero each side (the ghost nodes), and one coarse row.
    std::vector<double> line(dc.x() + 2);
    std::vector<T> coarse_row(dc.x());
#pragma omp for schedule(static)
    for (std::int64_t s = 0; s < static_cast<std::int64_t>(spans.size()); ++s) {
      const NodeSpan& span = spans[s];
      const AxisWeights wz = axis_weights(span.k), wy = axis_weights(span.j);
      // Fine i odd sits on coarse (i - 1) / 2, even i halfway between i/2 - 1
      // and i/2: the span reads coarse columns c0 <= i < c1.
      const int c0 = std::max(0, span.begin / 2 - 1), c1 = std::min(dc.x(), span.end / 2 + 1);
      std::fill(line.begin() + c0, line.begin() + c1 + 2, 0.0);
      for (int cz = 0; cz < 2; ++cz) {
        const double az = cz ? wz.w1 : wz.w0;
        const int kc = cz ? wz.c1 : wz.c0;
        if (az == 0.0 || kc < 0 || kc >= dc.z()) continue;
        for (int cy = 0; cy < 2; ++cy) {
          const double ay = cy ? wy.w1 : wy.w0;
          const int jc = cy ? wy.c1 : wy.c0;
          if (ay == 0.0 || jc < 0 || jc >= dc.y()) continue;
          coarse_nodes.gather_row(ec, jc, kc, c0, c1, coarse_row.data());
          for (int i = c0; i < c1; ++i) line[i + 1] += az * ay * coarse_row[i - c0];
        }
      }
      T* dst = x + (span.first - span.begin);  // dst[i]: node i of the span
      for (int i = span.begin; i < span.end; ++i) {
        dst[i] += static_cast<T>(i % 2 == 1 ? line[(i - 1) / 2 + 1] : 0.5 * (line[i / 2] + line[i / 2 + 1]));
      }
    }
  }
}

}  // namespace

template <typename T>
void prolongate_add(const GridGeometry& coarse,
                    const ActiveNodes& coarse_nodes,
                    const T* ec,
                    const GridGeometry& /*fine*/,
                    const ActiveNodes& fine_active,
                    T* x) {
  prolongate_add_spans(coarse, coarse_nodes, ec, fine_active.spans(), fine_active.count(), x);
}

void prolongate_add_to_stored(const GridGeometry& coarse,
                              const ActiveNodes& coarse_nodes,
                              const double* ec,
                              const ActiveNodes& fine_nodes,
                              double* x) {
  prolongate_add_spans(coarse, coarse_nodes, ec, fine_nodes.stored_spans(), fine_nodes.storage_size(), x);
}

template void restrict_to_coarse<float>(
    const GridGeometry&, const ActiveNodes&, const float*, const GridGeometry&, const ActiveNodes&, float*);
template void restrict_to_coarse<double>(
    const GridGeometry&, const ActiveNodes&, const double*, const GridGeometry&, const ActiveNodes&, double*);
template void prolongate_add<float>(
    const GridGeometry&, const ActiveNodes&, const float*, const GridGeometry&, const ActiveNodes&, float*);
template void prolongate_add<double>(
    const GridGeometry&, const ActiveNodes&, const double*, const GridGeometry&, const ActiveNodes&, double*);

void restrict_to_coarse(const GridGeometry& fine,
                        const std::vector<double>& r,
                        const GridGeometry& coarse,
                        std::vector<double>& rc) {
  assign_large(rc, coarse.num_nodes());
  restrict_to_coarse(fine, ActiveNodes::all(fine), r.data(), coarse, ActiveNodes::all(coarse), rc.data());
}

void prolongate_add(const GridGeometry& coarse,
                    const std::vector<double>& ec,
                    const GridGeometry& fine,
                    std::vector<double>& x) {
  prolongate_add(coarse, ActiveNodes::all(coarse), ec.data(), fine, ActiveNodes::all(fine), x.data());
}

}  // namespace hos::recon
