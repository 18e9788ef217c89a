// GIMP with analytic weighting functions (Thesis eq. 3.14-3.15). The particle domain is an
// axis-aligned box whose half-lengths follow det F: l_p = l_p^0 det(F_p)^(1/ndim)
// (Thesis eq. 3.23, Post eq. 28).
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "core/inline.hpp"
#include "shape/separable.hpp"

namespace skred {

// 1D GIMP weighting function and its gradient for node distance r = x_p - x_i, cell size L
// and particle half-length l (Thesis eq. 3.14; requires l <= L/2).
SKRED_INLINE void gimp_1d(double r, double L, double l, double& w, double& g) {
  if (r <= -L - l || r >= L + l) {
    w = 0.0;
    g = 0.0;
  } else if (r <= -L + l) {
    const double s = L + l + r;
    w = s * s / (4 * L * l);
    g = s / (2 * L * l);
  } else if (r <= -l) {
    w = 1.0 + r / L;
    g = 1.0 / L;
  } else if (r <= l) {
    w = 1.0 - (r * r + l * l) / (2 * L * l);
    g = -r / (L * l);
  } else if (r <= L - l) {
    w = 1.0 - r / L;
    g = -1.0 / L;
  } else {
    const double s = L + l - r;
    w = s * s / (4 * L * l);
    g = -s / (2 * L * l);
  }
}

// Eq. 3.14 at the three nodes nearest a point, in cell units: e = x_p/L - n in [-1/2, 1/2]
// is the offset from the nearest node n, lam = l/L in (0, 1/2] the half-length and inv = 1/lam.
// Nodes n - 1, n, n + 1 get w[0..2]; g[] are d/dx in cell units. Same regions as gimp_1d,
// without branches. T is double, or a vector of the three axes' values side by side (GCC/Clang
// vector extensions: the comparisons give lane masks, and ?: selects lane by lane).
template <class T>
SKRED_INLINE void gimp_3nodes(T e, T lam, T inv, T* w, T* g) {
  const T zero{}, one = zero + 1.0;
  const T tl = lam - e, tr = lam + e;
  const T sl = tl < zero ? zero : tl, sr = tr < zero ? zero : tr;  // overlaps of the tails
  const auto left = e <= -lam, right = e >= lam;                   // the point's domain lies within one cell
  w[0] = left ? -e : 0.25 * sl * sl * inv;
  g[0] = left ? -one : -0.5 * sl * inv;
  w[2] = right ? e : 0.25 * sr * sr * inv;
  g[2] = right ? one : 0.5 * sr * inv;
  const auto linear = left | right;
  const T abs_e = e < zero ? -e : e;
  w[1] = linear ? one - abs_e : one - 0.5 * (e * e + lam * lam) * inv;
  g[1] = linear ? (e > zero ? -one : one) : -e * inv;
}

// det(F)^(-1/3) for the 3D half-lengths (eq. 3.23) and their inverses, for J = det(F) in
// (1e-200, 1e200), without a division: a first guess from the exponent bits (within 3.5 %)
// refined by four Newton steps y <- y (4 - J y^3)/3, each taking the relative error e to
// about -2 e^2 (3.5e-2 -> 2.4e-3 -> 1.2e-5 -> 3e-10 -> round-off). The library's cbrt, or a
// root by Halley steps, costs divisions, the slowest arithmetic of a point's weights.
// Its two parts, the guess and a step, also run in the lanes of GimpKernel<3>::sizes.
SKRED_INLINE double gimp_cube_root_guess(double J) {
  return std::bit_cast<double>(0x553EF1A9FBE76C00ull - std::bit_cast<std::uint64_t>(J) / 3);
}
SKRED_INLINE double gimp_cube_root_step(double J, double y) {
  return y * ((4.0 - J * (y * y * y)) * (1.0 / 3.0));
}
inline constexpr int kGimpCubeRootSteps = 4;
SKRED_INLINE double gimp_inverse_cube_root(double J) {
  double y = gimp_cube_root_guess(J);
  for (int k = 0; k < kGimpCubeRootSteps; ++k) y = gimp_cube_root_step(J, y);
  return y;
}

// Stored without the middle weight, which is at least 1/2.
template <int D>
struct GimpKernel : SeparableKernel<GimpKernel<D>, D, 3, 1> {
  static constexpr int S = 3;
  using typename SeparableKernel<GimpKernel<D>, D, 3, 1>::Shape;
  static constexpr const char* name = "gimp";

  // The point's half-lengths in cell units, l_p / L = l_p^0 det(F)^(1/ndim) / L (eq. 3.23), kept
  // within (0, 1/2] so the support spans three nodes, and their inverses. They depend on F
  // only: a loop that moves points forms the next point's while it moves this one
  // (transfer/size_ahead.hpp; their root and divisions are the longest chain of the weights).
  struct Size {
    double lam[D], inv[D];
  };
  SKRED_INLINE Size size(const GridGeometry<D>& g, const Vec<D>& half0, const Mat<D>& F) const {
    return size_at(g, half0, F.determinant());
  }
  // size() from J = det(F).
  SKRED_INLINE Size size_at(const GridGeometry<D>& g, const Vec<D>& half0, double J) const {
    const double inv_h = 1.0 / g.h;
    Size s;
    if constexpr (D == 3) {
      const double h[3] = {half0[0], half0[1], half0[2]};
      if (root_in_range(J, h)) {
        from_root(g, J, gimp_inverse_cube_root(J), h, s.lam, s.inv);
        return s;
      }
    }
    const double scale = (D == 2) ? std::sqrt(std::max(J, 0.0)) : std::cbrt(J);
    for (int d = 0; d < D; ++d) {
      s.lam[d] = std::clamp(half0[d] * scale * inv_h, 1e-12, 0.5);
      s.inv[d] = 1.0 / s.lam[d];
    }
    return s;
  }
  // The 3D half-lengths from y = J^(-1/3): one division per point, J^(1/3) = J y^2 and
  // 1/lam_d = y L / l0_d, the three 1/l0_d from 1/(l0_x l0_y l0_z); the inverses clamped to
  // [2, 1e12] as lam to [1e-12, 1/2]. For J and l0 where root_in_range holds.
  SKRED_INLINE static bool root_in_range(double J, const double (&h)[3]) {
    return J > 1e-200 && J < 1e200 && h[0] * h[1] * h[2] > 1e-100;
  }
  SKRED_INLINE static void from_root(const GridGeometry<D>& g, double J, double y, const double (&h)[3],
                                     double (&lam)[3], double (&inv)[3]) requires(D == 3) {
    const double inv_h = 1.0 / g.h;
    const double scale = J * y * y, q = g.h * y / (h[0] * h[1] * h[2]);
    const double inv0[3] = {h[1] * h[2], h[0] * h[2], h[0] * h[1]};
    for (int d = 0; d < 3; ++d) {
      lam[d] = std::clamp(h[d] * scale * inv_h, 1e-12, 0.5);
      inv[d] = std::clamp(inv0[d] * q, 2.0, 1e12);
    }
  }
  // size() of `count` <= 8 consecutive points at once: the root's Newton steps, the division
  // and the clamps of eight points in the lanes of vectors. The same operations as size(), so the
  // same results; a point outside size()'s range of J and l0 takes size() itself.
  static constexpr int kSizeLanes = 8;
  SKRED_INLINE void sizes(const GridGeometry<D>& g, const Vec<D>* __restrict half0,
                          const Mat<D>* __restrict F, int count, Size* __restrict out) const
      requires(D == 3) {
    // (a loop over all lanes: over `count` alone, the compiler pairs the determinants'
    // products into other multiply-adds, and J changes at round-off)
    alignas(64) double J[kSizeLanes];
    for (int l = 0; l < kSizeLanes; ++l) J[l] = l < count ? F[l].determinant() : 1.0;
    sizes_at(g, half0, J, count, out);
  }
  // sizes() from the points' J = det(F).
  SKRED_INLINE void sizes_at(const GridGeometry<D>& g, const Vec<D>* __restrict half0,
                             const double* __restrict det_f, int count, Size* __restrict out) const
      requires(D == 3) {
    constexpr int L = kSizeLanes;
    alignas(64) double J[L], y[L], h[L][3];
    for (int l = 0; l < L; ++l) {
      const bool real = l < count;
      J[l] = real ? det_f[l] : 1.0;
      for (int d = 0; d < 3; ++d) h[l][d] = real ? half0[l][d] : 1.0;
    }
    for (int l = 0; l < L; ++l) y[l] = gimp_cube_root_guess(J[l]);
    for (int k = 0; k < kGimpCubeRootSteps; ++k)
      for (int l = 0; l < L; ++l) y[l] = gimp_cube_root_step(J[l], y[l]);
    Size lanes[L];
    for (int l = 0; l < L; ++l) from_root(g, J[l], y[l], h[l], lanes[l].lam, lanes[l].inv);
    for (int l = 0; l < count; ++l)
      out[l] = root_in_range(J[l], h[l]) ? lanes[l] : size_at(g, half0[l], J[l]);
  }
  SKRED_INLINE bool shape(const GridGeometry<D>& g, const Vec<D>& x, const Size& size, Shape& sh) const {
    const double inv_h = 1.0 / g.h;
    std::array<int, D> start{};
    double e[D];  // offsets from the nearest nodes, in cell units
    for (int d = 0; d < D; ++d) {
      const double xi = (x[d] - g.origin[d]) * inv_h;
      const double n = std::floor(xi + 0.5);  // nearest node
      start[d] = static_cast<int>(n) - 1 + GridGeometry<D>::pad;
      e[d] = xi - n;
    }
    if constexpr (D == 3) {
      // the three axes side by side, in lanes 0-2 of 4-wide vectors (lane 3: a point at a
      // node, half-length 1/2)
      using V4 = double __attribute__((vector_size(32)));
      const V4 ev = {e[0], e[1], e[2], 0.0};
      const V4 lam = {size.lam[0], size.lam[1], size.lam[2], 0.5};
      const V4 inv = {size.inv[0], size.inv[1], size.inv[2], 2.0};
      V4 w[S], gr[S];
      gimp_3nodes(ev, lam, inv, w, gr);
      for (int d = 0; d < D; ++d)
        for (int a = 0; a < S; ++a) {
          sh.w[d][a] = w[a][d];
          sh.g[d][a] = gr[a][d] * inv_h;
        }
    } else {
      for (int d = 0; d < D; ++d) {
        gimp_3nodes(e[d], size.lam[d], size.inv[d], sh.w[d], sh.g[d]);
        for (int a = 0; a < S; ++a) sh.g[d][a] *= inv_h;
      }
    }
    return block_base<D, S>(g, start, sh.base);
  }
  SKRED_INLINE bool shape(const GridGeometry<D>& g, const Vec<D>& x, const Vec<D>& half0, const Mat<D>& F,
                          Shape& sh) const {
    return shape(g, x, size(g, half0, F), sh);
  }
};

}  // namespace skred
