// The result of evaluating an interpolation kernel for one material point: the weighting
// functions N_ip and their gradients dN_ip/dx on a fixed S^D block of grid nodes.
#pragma once
#include <array>
#include <cstddef>

#include "core/grid.hpp"
#include "core/types.hpp"

namespace skred {

constexpr int ipow(int b, int e) { return e == 0 ? 1 : b * ipow(b, e - 1); }

template <int D, int S>
struct Stencil {
  static constexpr int size = ipow(S, D);
  static constexpr int width = S;
  std::size_t base = 0;             // flat index of the block's first node
  std::array<double, size> w{};     // weighting functions N_ip (Thesis eq. 2.46)
  std::array<Vec<D>, size> grad{};  // gradient weighting functions (Thesis eq. 2.47)
};

// Flat-index offsets of the S^D block relative to its first node; entry k has the
// multi-index (k mod S, (k / S) mod S, ...), axis 0 fastest.
template <int D, int S>
struct StencilOffsets {
  std::array<std::size_t, ipow(S, D)> off{};
  explicit StencilOffsets(const GridGeometry<D>& g) {
    for (int k = 0; k < ipow(S, D); ++k) {
      std::size_t o = 0;
      int r = k;
      for (int d = 0; d < D; ++d) {
        o += static_cast<std::size_t>(r % S) * g.stride(d);
        r /= S;
      }
      off[static_cast<std::size_t>(k)] = o;
    }
  }
};

// Flat index of the block whose first node has padded per-axis index start[d]; false if
// the block does not fit inside the grid (the point has left the domain).
template <int D, int S>
inline bool block_base(const GridGeometry<D>& g, const std::array<int, D>& start, std::size_t& base) {
  std::size_t b = 0;
  for (int d = 0; d < D; ++d) {
    if (start[d] < 0 || start[d] + S > g.nodes(d)) return false;
    b += static_cast<std::size_t>(start[d]) * g.stride(d);
  }
  base = b;
  return true;
}

// Tensor product of 1D weights and derivatives (Thesis eq. 3.15).
template <int D, int S>
inline void tensor_product(const double (&w1)[D][S], const double (&g1)[D][S], Stencil<D, S>& st) {
  if constexpr (D == 2) {
    for (int b = 0; b < S; ++b)
      for (int a = 0; a < S; ++a) {
        const int k = a + S * b;
        st.w[k] = w1[0][a] * w1[1][b];
        st.grad[k] = Vec<2>(g1[0][a] * w1[1][b], w1[0][a] * g1[1][b]);
      }
  } else {
    static_assert(D == 3, "skred supports 2D and 3D");
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b)
        for (int a = 0; a < S; ++a) {
          const int k = a + S * (b + S * c);
          st.w[k] = w1[0][a] * w1[1][b] * w1[2][c];
          st.grad[k] = Vec<3>(g1[0][a] * w1[1][b] * w1[2][c], w1[0][a] * g1[1][b] * w1[2][c],
                              w1[0][a] * w1[1][b] * g1[2][c]);
        }
  }
}

}  // namespace skred
