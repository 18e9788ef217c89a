// The functions over one cell of the grid that Acosta's remedies are built from (seed 001
// §5.3-5.5): the cell's bilinear (trilinear) shape functions N_a and their gradients at its
// Gauss points, the local GIMP function S_ip* of a support domain clipped to the cell (§5.4,
// fig. 16d), and the Lagrange functions of the composite material point method over a row of
// nodes (CMPM, eq. 21-23). Plain functions of local coordinates; mapped_stencils.hpp combines
// them per point.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>

#include "core/types.hpp"

namespace skred::cell {

inline constexpr int corners(int D) { return 1 << D; }

// The 1D Gauss points of the cell's 2-point rule in cell units t = (x - x_0) / h in [0, 1]:
// (1 -+ 1/sqrt(3)) / 2.
inline double gauss_t(int side) {
  const double a = 0.5 / std::sqrt(3.0);
  return side ? 0.5 + a : 0.5 - a;
}

// Corner a's bilinear shape function at cell coordinates t (corner bit d: the node at t_d = 1).
template <int D>
inline double corner_weight(int a, const Vec<D>& t) {
  double w = 1.0;
  for (int d = 0; d < D; ++d) w *= ((a >> d) & 1) ? t[d] : 1.0 - t[d];
  return w;
}

// Its gradient dN_a/dx at t for cells of size h.
template <int D>
inline Vec<D> corner_gradient(int a, const Vec<D>& t, double h) {
  Vec<D> g;
  for (int d = 0; d < D; ++d) {
    double w = ((a >> d) & 1) ? 1.0 / h : -1.0 / h;
    for (int e = 0; e < D; ++e)
      if (e != d) w *= ((a >> e) & 1) ? t[e] : 1.0 - t[e];
    g[d] = w;
  }
  return g;
}

// Gauss point g's cell coordinates (bit d of g: the upper point along d).
template <int D>
inline Vec<D> gauss_point(int g) {
  Vec<D> t;
  for (int d = 0; d < D; ++d) t[d] = gauss_t((g >> d) & 1);
  return t;
}

// The local GIMP functions of one axis (Acosta §5.4, eq. 20, fig. 16d): the cell's two linear
// functions averaged over the part of the support [t - l, t + l] (cell units) that lies in the
// cell [0, 1], divided by the support's length 2 l. Their sum is the share of the support in the
// cell; the shares of the cells it spans add up to one.
inline std::array<double, 2> local_gimp(double t, double l) {
  const double a = std::max(t - l, 0.0), b = std::min(t + l, 1.0);
  if (!(b > a)) return {0.0, 0.0};
  const double share = (b - a) / (2.0 * l), mid = 0.5 * (a + b);
  return {share * (1.0 - mid), share * mid};
}

// The Lagrange functions over n nodes at positions xs (eq. 21; n = 4: the C2 functions of
// eq. 22 for a cell with both neighbours, n = 3: the C1 functions of eq. 23 at a boundary, n = 2:
// the linear ones) and their derivatives, at x.
struct Lagrange1D {
  std::array<double, 4> value{}, slope{};
};
inline Lagrange1D lagrange(const double* xs, int n, double x) {
  Lagrange1D L;
  for (int j = 0; j < n; ++j) {
    double v = 1.0, s = 0.0;
    for (int m = 0; m < n; ++m) {
      if (m == j) continue;
      const double inv = 1.0 / (xs[j] - xs[m]);
      // d/dx of prod (x - xs_m) inv: the product rule over the factors so far.
      s = s * (x - xs[m]) * inv + v * inv;
      v *= (x - xs[m]) * inv;
    }
    L.value[static_cast<std::size_t>(j)] = v;
    L.slope[static_cast<std::size_t>(j)] = s;
  }
  return L;
}

}  // namespace skred::cell
