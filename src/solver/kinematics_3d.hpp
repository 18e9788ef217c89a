// The kinematic end of a 3D point update written out in scalars, like the plane-strain one in
// stress_update.hpp: it runs twice per point and step, and Eigen's 3 x 3 products on the
// column-major Mat3 and the 6-vector round trips through to_matrix/to_voigt cost more than
// the arithmetic. g = dt grad v (row i, column j: dt dv_i/dx_j), dF = I + g.
#pragma once
#include "core/inline.hpp"
#include "core/types.hpp"

namespace skred {

struct StressUpdateResult {
  double strain_energy = 0.0;  // stored: V (sigma^{k+1} + sigma^k)/2 : (d_eps - d_eps_p)  (eq. 4.16)
  double dissipation = 0.0;    // plastic work V (sigma^{k+1} + sigma^k)/2 : d_eps_p
  double volume = 0.0;         // V_p^{k+1} = det(F^{k+1}) V_p^0
};

namespace kinematics3 {

// d_eps = sym(g) (Thesis eq. 2.20) in Voigt order [xx, yy, zz, xy, yz, xz].
SKRED_INLINE Sym3 strain_increment(const double (&g)[3][3]) {
  Sym3 e;
  e << g[0][0], g[1][1], g[2][2], 0.5 * (g[0][1] + g[1][0]), 0.5 * (g[1][2] + g[2][1]),
      0.5 * (g[0][2] + g[2][0]);
  return e;
}

// sigma = dF S dF^T / det dF (Thesis eq. 4.4) on the Voigt components s, in place. T is a
// double, or a vector of eight points' values side by side (solver/stress_lanes_3d.hpp).
template <class T>
SKRED_INLINE void push_forward(const T (&g)[3][3], T (&s)[6]) {
  T a[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[i][j] = i == j ? g[i][j] + 1.0 : g[i][j];
  const T m[3][3] = {{s[0], s[3], s[5]}, {s[3], s[1], s[4]}, {s[5], s[4], s[2]}};
  T b[3][3];  // dF S
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b[i][j] = a[i][0] * m[0][j] + a[i][1] * m[1][j] + a[i][2] * m[2][j];
  const T det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  const T inv_j = 1.0 / det;
  auto c = [&](int i, int j) { return (b[i][0] * a[j][0] + b[i][1] * a[j][1] + b[i][2] * a[j][2]) * inv_j; };
  // (dF S dF^T is symmetric up to round-off; the symmetric part, as to_voigt takes it.)
  const T out[6] = {c(0, 0),
                    c(1, 1),
                    c(2, 2),
                    0.5 * (c(0, 1) + c(1, 0)),
                    0.5 * (c(1, 2) + c(2, 1)),
                    0.5 * (c(0, 2) + c(2, 0))};
  for (int k = 0; k < 6; ++k) s[k] = out[k];
}
SKRED_INLINE void push_forward(const double (&g)[3][3], Sym3& s) {
  double v[6] = {s[0], s[1], s[2], s[3], s[4], s[5]};
  push_forward(g, v);
  s << v[0], v[1], v[2], v[3], v[4], v[5];
}

// F <- dF F (eq. 3.2), Fe <- (I + d_eps - d_eps_p) Fe (Post eq. 72-73), V = det F V0 and the
// trapezoidal stress work (eq. 4.16) split into its stored and dissipated parts, given the
// updated stress. Plastic = false: d_eps_p = 0.
template <bool Plastic>
SKRED_INLINE StressUpdateResult finish(const double (&g)[3][3], const Sym3& deps, const Sym3& deps_p,
                                       const Sym3& old, double volume0, const Sym3& stress, Mat3& F,
                                       Mat3& Fe) {
  double f[3][3], h[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) f[i][j] = F(i, j), h[i][j] = Fe(i, j);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) F(i, j) = f[i][j] + g[i][0] * f[0][j] + g[i][1] * f[1][j] + g[i][2] * f[2][j];
  Sym3 ee = deps;
  if constexpr (Plastic) ee -= deps_p;
  const double e[3][3] = {{ee[0], ee[3], ee[5]}, {ee[3], ee[1], ee[4]}, {ee[5], ee[4], ee[2]}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      Fe(i, j) = h[i][j] + e[i][0] * h[0][j] + e[i][1] * h[1][j] + e[i][2] * h[2][j];
  const double det = F(0, 0) * (F(1, 1) * F(2, 2) - F(1, 2) * F(2, 1)) -
                     F(0, 1) * (F(1, 0) * F(2, 2) - F(1, 2) * F(2, 0)) +
                     F(0, 2) * (F(1, 0) * F(2, 1) - F(1, 1) * F(2, 0));
  const double volume = volume0 * det;
  const Sym3 mid = old + stress;
  const double half_v = 0.5 * volume;
  if constexpr (!Plastic) return {half_v * contract(mid, ee), 0.0, volume};
  return {half_v * contract(mid, ee), half_v * contract(mid, deps_p), volume};
}

}  // namespace kinematics3
}  // namespace skred
