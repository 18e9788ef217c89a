// Separable kernels (linear, GIMP, B-spline) are tensor products of 1D weighting functions
// (Thesis eq. 3.15). The solver evaluates a point's 1D functions once per time step, keeps
// them in packed form through the phases of the step, and expands the tensor product on the
// fly while it scatters to or gathers from the S^D block of nodes.
#pragma once
#include <cstddef>
#include <cstdint>

#include "shape/stencil.hpp"

namespace skred {

// Per axis the S 1D weighting functions and their derivatives, and the flat index of the
// block's first node.
template <int D, int S> struct Separable {
  std::size_t base = 0;
  double w[D][S];
  double g[D][S];
};

// Storage form of Separable between the phases of a step. The 1D functions of every kernel
// are a partition of unity (sum w = 1, sum g = 0 on each axis), so the entry `Skip`, chosen
// per kernel as one that never comes near zero, is not stored but recovered from the others.
template <int D, int S, int Skip> struct PackedSeparable {
  std::int64_t base = 0;
  double w[D][S - 1];
  double g[D][S - 1];

  [[gnu::always_inline]] void pack(const Separable<D, S>& s) {
    base = static_cast<std::int64_t>(s.base);
    for (int d = 0; d < D; ++d)
      for (int a = 0, j = 0; a < S; ++a)
        if (a != Skip) {
          w[d][j] = s.w[d][a];
          g[d][j++] = s.g[d][a];
        }
  }
  [[gnu::always_inline]] void unpack(Separable<D, S>& s) const {
    s.base = static_cast<std::size_t>(base);
    for (int d = 0; d < D; ++d) {
      double sw = 0.0, sg = 0.0;
      for (int a = 0, j = 0; a < S; ++a)
        if (a != Skip) {
          s.w[d][a] = w[d][j];
          s.g[d][a] = g[d][j];
          sw += w[d][j];
          sg += g[d][j++];
        }
      s.w[d][Skip] = 1.0 - sw;
      s.g[d][Skip] = -sg;
    }
  }
};

// Flat-index strides of the grid axes, for walking a block of nodes.
template <int D> struct NodeStrides {
  std::size_t s[D];
  explicit NodeStrides(const GridGeometry<D>& g) {
    for (int d = 0; d < D; ++d) s[d] = g.stride(d);
  }
};

// Calls fn(node, N_ip, grad N_ip) for every node of the point's block (eq. 3.15).
template <int D, int S, class Fn>
[[gnu::always_inline]] inline void for_each_node(const Separable<D, S>& sh, const NodeStrides<D>& st,
                                                 Fn&& fn) {
  if constexpr (D == 2) {
    for (int b = 0; b < S; ++b) {
      const std::size_t row = sh.base + b * st.s[1];
      const double wy = sh.w[1][b], gy = sh.g[1][b];
      for (int a = 0; a < S; ++a)
        fn(row + a, sh.w[0][a] * wy, Vec<2>(sh.g[0][a] * wy, sh.w[0][a] * gy));
    }
  } else {
    static_assert(D == 3, "skred supports 2D and 3D");
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b) {
        const std::size_t row = sh.base + b * st.s[1] + c * st.s[2];
        const double wyz = sh.w[1][b] * sh.w[2][c];
        const double gy = sh.g[1][b] * sh.w[2][c], gz = sh.w[1][b] * sh.g[2][c];
        for (int a = 0; a < S; ++a)
          fn(row + a, sh.w[0][a] * wyz,
             Vec<3>(sh.g[0][a] * wyz, sh.w[0][a] * gy, sh.w[0][a] * gz));
      }
  }
}

// The same walk over a general (non-separable) stencil.
template <int D, int S, class Fn>
[[gnu::always_inline]] inline void for_each_node(const Stencil<D, S>& sh, const NodeStrides<D>& st,
                                                 Fn&& fn) {
  for (int k = 0; k < Stencil<D, S>::size; ++k) {
    std::size_t off = 0;
    int r = k;
    for (int d = 0; d < D; ++d) {
      off += static_cast<std::size_t>(r % S) * st.s[d];
      r /= S;
    }
    fn(sh.base + off, sh.w[k], sh.grad[k]);
  }
}

// A separable kernel's full stencil (for tests and post-processing).
template <int D, int S> inline void expand(const Separable<D, S>& sh, Stencil<D, S>& st) {
  st.base = sh.base;
  tensor_product<D, S>(sh.w, sh.g, st);
}

}  // namespace skred
