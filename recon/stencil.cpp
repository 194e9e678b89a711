#include "recon/stencil.h"

#include <algorithm>
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

std::vector<StencilRow> Stencil::rows() const {
  std::vector<StencilRow> rows;
  for (std::size_t t = 0; t < offsets.size(); ++t) {
    const Eigen::Vector3i& o = offsets[t];
    auto it =
        std::find_if(rows.begin(), rows.end(), [&](const StencilRow& r) { return r.dy == o.y() && r.dz == o.z(); });
    if (it == rows.end()) {
      it = rows.insert(rows.end(), StencilRow{});
      it->dy = o.y();
      it->dz = o.z();
    }
    it->ox[it->count] = o.x();
    it->c[it->count++] = coefficients[t];
  }
  return rows;
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

}  // namespace hos::recon
