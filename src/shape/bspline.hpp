// Cubic B-spline interpolation on a clamped (open) knot vector. Per axis with n cells the
// knots are 0,0,0,0,1,2,...,n-1,n,n,n,n (cell units), giving n + 3 basis functions that are
// a partition of unity on the whole domain [0, n], non-negative and C2 inside. At a wall only
// the first (last) function is non-zero, so a velocity boundary condition on that DOF holds
// exactly at the wall: this is the boundary treatment (no basis function reaches beyond the
// domain). Away from the walls the functions are the uniform cubic B-splines of
// Steffen, Kirby & Berzins (2008), cited in Thesis §2.1.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/inline.hpp"
#include "shape/separable.hpp"

namespace skred {

// Values and derivatives (per unit of xi) of the four non-zero cubic basis functions on the
// cell containing xi, for an axis of n cells. Returns the DOF index of the first of them.
inline int bspline_1d(double xi, int n, double* w, double* g) {
  int k = static_cast<int>(std::floor(xi));
  k = std::clamp(k, 0, n - 1);
  const double u = xi - k;
  if (k >= 2 && k <= n - 3) {  // uniform knots around this cell
    const double v = 1.0 - u, u2 = u * u, u3 = u2 * u;
    w[0] = v * v * v / 6.0;
    w[1] = (3 * u3 - 6 * u2 + 4) / 6.0;
    w[2] = (-3 * u3 + 3 * u2 + 3 * u + 1) / 6.0;
    w[3] = u3 / 6.0;
    g[0] = -0.5 * v * v;
    g[1] = 0.5 * (3 * u2 - 4 * u);
    g[2] = 0.5 * (-3 * u2 + 2 * u + 1);
    g[3] = 0.5 * u2;
    return k;
  }
  // Cox-de Boor recursion on the clamped knots (The NURBS Book, A2.2), knot span i = k + 3.
  auto t = [n](int m) { return static_cast<double>(std::clamp(m - 3, 0, n)); };
  const int i = k + 3;
  double left[4], right[4], N[4][4];  // N[j][r]: degree-j function r of the span
  N[0][0] = 1.0;
  for (int j = 1; j <= 3; ++j) {
    left[j] = xi - t(i + 1 - j);
    right[j] = t(i + j) - xi;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double den = right[r + 1] + left[j - r];
      const double tmp = den > 0 ? N[j - 1][r] / den : 0.0;
      N[j][r] = saved + right[r + 1] * tmp;
      saved = left[j - r] * tmp;
    }
    N[j][j] = saved;
  }
  for (int r = 0; r < 4; ++r) w[r] = N[3][r];
  // Derivative of the degree-3 function of DOF q = k + r from the degree-2 functions:
  // N'_{q,3} = 3 (N_{q,2} / (t_{q+3} - t_q) - N_{q+1,2} / (t_{q+4} - t_{q+1})).
  auto n2 = [&](int r) { return (r >= 1 && r <= 3) ? N[2][r - 1] : 0.0; };  // N_{k+r,2}
  for (int r = 0; r < 4; ++r) {
    const int q = k + r;
    const double d1 = t(q + 3) - t(q), d2 = t(q + 4) - t(q + 1);
    g[r] = 3.0 * ((d1 > 0 ? n2(r) / d1 : 0.0) - (d2 > 0 ? n2(r + 1) / d2 : 0.0));
  }
  return k;
}

// Stored without the second weight (at least 1/6 away from the walls, exact at them).
template <int D>
struct BsplineKernel : SeparableKernel<BsplineKernel<D>, D, 4, 1> {
  static constexpr int S = 4;
  using typename SeparableKernel<BsplineKernel<D>, D, 4, 1>::Shape;
  static constexpr const char* name = "bspline";
  static constexpr bool apic_inertia = true;  // APIC's C_p = B_p D_p^-1 (apic_affine_velocity)

  SKRED_INLINE bool shape(const GridGeometry<D>& g, const Vec<D>& x, const Vec<D>& /*half0*/,
                          const Mat<D>& /*F*/, Shape& sh) const {
    std::array<int, D> start{};
    const double inv_h = 1.0 / g.h;
    for (int d = 0; d < D; ++d) {
      const double xi = (x[d] - g.origin[d]) * inv_h;
      if (!(xi >= 0.0 && xi <= g.cells[d])) return false;  // no basis outside the domain
      start[d] = bspline_1d(xi, g.cells[d], sh.w[d], sh.g[d]);
      for (int a = 0; a < S; ++a) sh.g[d][a] *= inv_h;
    }
    return block_base<D, S>(g, start, sh.base);
  }
};

}  // namespace skred
