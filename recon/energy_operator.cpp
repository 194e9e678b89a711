#include "recon/energy_operator.h"

#include <cmath>
#include <map>

namespace hos::recon {
namespace {

using StencilMap = std::map<std::array<int, 3>, double>;

StencilMap convolve(const StencilMap& a, const StencilMap& b) {
  StencilMap out;
  for (const auto& [oa, ca] : a) {
    for (const auto& [ob, cb] : b) {
      out[{oa[0] + ob[0], oa[1] + ob[1], oa[2] + ob[2]}] += ca * cb;
    }
  }
  return out;
}

void accumulate(StencilMap& into, const StencilMap& s, double w) {
  for (const auto& [o, c] : s) into[o] += w * c;
}

// Paper eq. (9): second differences and the cross differences.
StencilMap pure_second(int axis, double h) {
  std::array<int, 3> m{0, 0, 0}, p{0, 0, 0};
  m[axis] = -1;
  p[axis] = 1;
  const double s = 1.0 / (h * h);
  return {{m, s}, {{0, 0, 0}, -2.0 * s}, {p, s}};
}

StencilMap mixed_second(int a, int b, double h) {
  const double s = 1.0 / (4.0 * h * h);
  StencilMap out;
  for (int sa : {-1, 1}) {
    for (int sb : {-1, 1}) {
      std::array<int, 3> o{0, 0, 0};
      o[a] = sa;
      o[b] = sb;
      out[o] = s * sa * sb;
    }
  }
  return out;
}

StencilMap negative_laplacian(double h) {
  StencilMap out;
  const double s = 1.0 / (h * h);
  out[{0, 0, 0}] = 6.0 * s;
  for (int a = 0; a < 3; ++a) {
    std::array<int, 3> o{0, 0, 0};
    o[a] = 1;
    out[o] = -s;
    o[a] = -1;
    out[o] = -s;
  }
  return out;
}

}  // namespace

double Stencil::center() const {
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    if (offsets[k].isZero()) return coefficients[k];
  }
  return 0.0;
}

double Stencil::abs_sum() const {
  double s = 0.0;
  for (double c : coefficients) s += std::abs(c);
  return s;
}

Stencil energy_stencil(SmoothnessEnergy energy, double h, double hessian_weight) {
  StencilMap total = negative_laplacian(h);
  StencilMap hessian;
  switch (energy) {
    case SmoothnessEnergy::kMembrane:
      // |grad f|^2 as smoothness: H = -Lap.
      hessian = negative_laplacian(h);
      break;
    case SmoothnessEnergy::kTotalVariation:
      break;  // per-node weights, see EnergyOperator
    case SmoothnessEnergy::kPureSecond:
    case SmoothnessEnergy::kFullHessian:
      for (int a = 0; a < 3; ++a) {
        const StencilMap d = pure_second(a, h);
        accumulate(hessian, convolve(d, d), 1.0);
      }
      if (energy == SmoothnessEnergy::kFullHessian) {
        for (int a = 0; a < 3; ++a) {
          for (int b = a + 1; b < 3; ++b) {
            const StencilMap d = mixed_second(a, b, h);
            accumulate(hessian, convolve(d, d), 2.0);
          }
        }
      }
      break;
  }
  accumulate(total, hessian, 2.0 * hessian_weight);
  Stencil s;
  for (const auto& [o, c] : total) {
    if (c == 0.0) continue;
    s.offsets.emplace_back(o[0], o[1], o[2]);
    s.coefficients.push_back(c);
  }
  return s;
}

EnergyOperator::EnergyOperator(const GridGeometry& geometry, SmoothnessEnergy energy,
                               double hessian_weight, std::vector<double> tv_node_weights,
                               double tv_weight)
    : geometry_(geometry),
      energy_(energy),
      hessian_weight_(hessian_weight),
      stencil_(energy_stencil(energy, geometry.spacing, hessian_weight)),
      tv_node_weights_(std::move(tv_node_weights)),
      tv_weight_(tv_weight) {
  for (const auto& o : stencil_.offsets) {
    linear_offsets_.push_back(geometry_.index(o.x(), o.y(), o.z()));
  }
  stencil_abs_sum_ = stencil_.abs_sum();
}

void EnergyOperator::apply(const std::vector<double>& x, std::vector<double>& y) const {
  const GridGeometry& g = geometry_;
  const Eigen::Vector3i d = g.dims;
  y.resize(x.size());
  const std::size_t n = stencil_.offsets.size();
  const double* c = stencil_.coefficients.data();
  const std::int64_t* lo = linear_offsets_.data();
  const bool tv = !tv_node_weights_.empty();
  const double tv_scale = tv_weight_ / (g.spacing * g.spacing);
  const std::int64_t strides[3] = {1, d.x(), std::int64_t{d.x()} * d.y()};
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < d.z(); ++k) {
    for (int j = 0; j < d.y(); ++j) {
      const bool row_inside = k >= 2 && k < d.z() - 2 && j >= 2 && j < d.y() - 2;
      for (int i = 0; i < d.x(); ++i) {
        const std::int64_t idx = g.index(i, j, k);
        double s = 0.0;
        if (row_inside && i >= 2 && i < d.x() - 2) {
          for (std::size_t t = 0; t < n; ++t) s += c[t] * x[idx + lo[t]];
        } else {
          for (std::size_t t = 0; t < n; ++t) {
            const Eigen::Vector3i& o = stencil_.offsets[t];
            if (g.contains(i + o.x(), j + o.y(), k + o.z())) s += c[t] * x[idx + lo[t]];
          }
        }
        if (tv) {
          // -div(w grad x) with edge weights (w_i + w_j) / 2; ghosts are zero.
          const Eigen::Vector3i p(i, j, k);
          const double wi = tv_node_weights_[idx];
          double t = 0.0;
          for (int a = 0; a < 3; ++a) {
            for (int sgn : {-1, 1}) {
              const bool inside = sgn > 0 ? p[a] < d[a] - 1 : p[a] > 0;
              const std::int64_t nb = idx + sgn * strides[a];
              const double wj = inside ? tv_node_weights_[nb] : wi;
              t += 0.5 * (wi + wj) * (x[idx] - (inside ? x[nb] : 0.0));
            }
          }
          s += tv_scale * t;
        }
        y[idx] = s;
      }
    }
  }
  if (screening_) {
    // Exact S^T S x on the finest level: interpolate at the samples, splat back.
    const auto& sc = *screening_;
    const std::int64_t n_nodes = g.num_nodes();
    std::int64_t corner_offsets[8];
    for (int c = 0; c < 8; ++c) corner_offsets[c] = g.index(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    for (std::size_t i = 0; i < sc.corner.size(); ++i) {
      double v = 0.0;
      for (int c = 0; c < 8; ++c) {
        const std::int64_t node = sc.corner[i] + corner_offsets[c];
        if (sc.weights[i][c] != 0.0f && node >= 0 && node < n_nodes) v += sc.weights[i][c] * x[node];
      }
      v *= sc.weight;
      for (int c = 0; c < 8; ++c) {
        const std::int64_t node = sc.corner[i] + corner_offsets[c];
        if (sc.weights[i][c] != 0.0f && node >= 0 && node < n_nodes) y[node] += sc.weights[i][c] * v;
      }
    }
  } else if (!screening_diagonal_.empty()) {
    const std::int64_t n_nodes = g.num_nodes();
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n_nodes; ++i) y[i] += screening_diagonal_[i] * x[i];
  }
}

void EnergyOperator::set_screening(const Screening* screening) {
  screening_ = screening;
  screening_diagonal_.assign(geometry_.num_nodes(), 0.0);
  if (!screening) return;
  for (std::size_t i = 0; i < screening->corner.size(); ++i) {
    for (int c = 0; c < 8; ++c) {
      const std::int64_t node = screening->corner[i] + geometry_.index(c & 1, (c >> 1) & 1, (c >> 2) & 1);
      if (node >= 0 && node < geometry_.num_nodes()) screening_diagonal_[node] += screening->weight * screening->weights[i][c];
    }
  }
}

double EnergyOperator::l1_diagonal(std::int64_t node) const {
  const double screen = screening_diagonal_.empty() ? 0.0 : screening_diagonal_[node];
  if (tv_node_weights_.empty()) return stencil_abs_sum_ + screen;
  // Each TV edge contributes its weight twice to the row's absolute sum; the
  // neighbour weights are bounded by the node's own plus the largest nearby,
  // so use the node weight and its neighbours' directly.
  const GridGeometry& g = geometry_;
  const Eigen::Vector3i d = g.dims;
  const int i = static_cast<int>(node % d.x());
  const int j = static_cast<int>((node / d.x()) % d.y());
  const int k = static_cast<int>(node / (std::int64_t{d.x()} * d.y()));
  const double wi = tv_node_weights_[node];
  double edges = 0.0;
  const int p[3] = {i, j, k};
  const std::int64_t strides[3] = {1, d.x(), std::int64_t{d.x()} * d.y()};
  for (int a = 0; a < 3; ++a) {
    edges += 0.5 * (wi + (p[a] > 0 ? tv_node_weights_[node - strides[a]] : wi));
    edges += 0.5 * (wi + (p[a] < d[a] - 1 ? tv_node_weights_[node + strides[a]] : wi));
  }
  return stencil_abs_sum_ + 2.0 * tv_weight_ / (g.spacing * g.spacing) * edges + screen;
}

EnergyOperator EnergyOperator::coarsened() const {
  const GridGeometry coarse = geometry_.coarsened();
  std::vector<double> weights;
  if (!tv_node_weights_.empty()) {
    restrict_to_coarse(geometry_, tv_node_weights_, coarse, weights);
  }
  EnergyOperator op(coarse, energy_, hessian_weight_, std::move(weights), tv_weight_);
  if (!screening_diagonal_.empty()) {
    // The coarse operator keeps the screening as a diagonal term (R D P).
    restrict_to_coarse(geometry_, screening_diagonal_, coarse, op.screening_diagonal_);
    for (double& v : op.screening_diagonal_) v *= 8.0;
  }
  return op;
}

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

void restrict_to_coarse(const GridGeometry& fine, const std::vector<double>& r,
                        const GridGeometry& coarse, std::vector<double>& rc) {
  rc.assign(coarse.num_nodes(), 0.0);
  const Eigen::Vector3i dc = coarse.dims;
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < dc.z(); ++k) {
    for (int j = 0; j < dc.y(); ++j) {
      for (int i = 0; i < dc.x(); ++i) {
        double s = 0.0;
        for (int oz = -1; oz <= 1; ++oz) {
          for (int oy = -1; oy <= 1; ++oy) {
            for (int ox = -1; ox <= 1; ++ox) {
              const int fi = 2 * i + 1 + ox, fj = 2 * j + 1 + oy, fk = 2 * k + 1 + oz;
              const double w = (ox ? 0.5 : 1.0) * (oy ? 0.5 : 1.0) * (oz ? 0.5 : 1.0);
              s += w * r[fine.index(fi, fj, fk)];
            }
          }
        }
        rc[coarse.index(i, j, k)] = s / 8.0;
      }
    }
  }
}

void prolongate_add(const GridGeometry& coarse, const std::vector<double>& ec,
                    const GridGeometry& fine, std::vector<double>& x) {
  const Eigen::Vector3i df = fine.dims;
  const auto value = [&](int i, int j, int k) {
    return coarse.contains(i, j, k) ? ec[coarse.index(i, j, k)] : 0.0;
  };
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < df.z(); ++k) {
    for (int j = 0; j < df.y(); ++j) {
      const AxisWeights wz = axis_weights(k), wy = axis_weights(j);
      for (int i = 0; i < df.x(); ++i) {
        const AxisWeights wx = axis_weights(i);
        double s = 0.0;
        for (int cz = 0; cz < 2; ++cz) {
          const double az = cz ? wz.w1 : wz.w0;
          if (az == 0.0) continue;
          for (int cy = 0; cy < 2; ++cy) {
            const double ay = cy ? wy.w1 : wy.w0;
            if (ay == 0.0) continue;
            for (int cx = 0; cx < 2; ++cx) {
              const double ax = cx ? wx.w1 : wx.w0;
              if (ax == 0.0) continue;
              s += az * ay * ax *
                   value(cx ? wx.c1 : wx.c0, cy ? wy.c1 : wy.c0, cz ? wz.c1 : wz.c0);
            }
          }
        }
        x[fine.index(i, j, k)] += s;
      }
    }
  }
}

}  // namespace hos::recon
