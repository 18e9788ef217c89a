// GIMP with analytic weighting functions (Thesis eq. 3.14-3.15). The particle domain is an
// axis-aligned box whose half-lengths follow det F: l_p = l_p^0 det(F_p)^(1/ndim)
// (Thesis eq. 3.23, Post eq. 28).
#pragma once
#include <algorithm>
#include <cmath>

#include "shape/stencil.hpp"

namespace skred {

// 1D GIMP weighting function and its gradient for node distance r = x_p - x_i, cell size L
// and particle half-length l (Thesis eq. 3.14; requires l <= L/2).
[[gnu::always_inline]] inline void gimp_1d(double r, double L, double l, double& w, double& g) {
  if (r <= -L - l || r >= L + l) { w = 0.0; g = 0.0; }
  else if (r <= -L + l) { const double s = L + l + r; w = s * s / (4 * L * l); g = s / (2 * L * l); }
  else if (r <= -l) { w = 1.0 + r / L; g = 1.0 / L; }
  else if (r <= l) { w = 1.0 - (r * r + l * l) / (2 * L * l); g = -r / (L * l); }
  else if (r <= L - l) { w = 1.0 - r / L; g = -1.0 / L; }
  else { const double s = L + l - r; w = s * s / (4 * L * l); g = -s / (2 * L * l); }
}

template <int D> struct GimpKernel {
  static constexpr int S = 3;
  using StencilT = Stencil<D, S>;
  static constexpr const char* name = "gimp";

  [[gnu::always_inline]] bool operator()(const GridGeometry<D>& g, const Vec<D>& x, const Vec<D>& half0,
                  const Mat<D>& F, StencilT& st) const {
    const double J = F.determinant();
    const double scale = (D == 2) ? std::sqrt(std::max(J, 0.0)) : std::cbrt(J);
    double w1[D][S], g1[D][S];
    std::array<int, D> start{};
    const double L = g.h;
    for (int d = 0; d < D; ++d) {
      // The half-length is kept within (0, L/2] so the support spans three nodes.
      const double l = std::clamp(half0[d] * scale, 1e-12 * L, 0.5 * L);
      const double xi = (x[d] - g.origin[d]) / L;
      const int n = static_cast<int>(std::floor(xi + 0.5));  // nearest node
      start[d] = n - 1 + GridGeometry<D>::pad;
      for (int a = 0; a < S; ++a) gimp_1d((xi - (n - 1 + a)) * L, L, l, w1[d][a], g1[d][a]);
    }
    if (!block_base<D, S>(g, start, st.base)) return false;
    tensor_product<D, S>(w1, g1, st);
    return true;
  }
};

}  // namespace skred
