// Linear (tent) shape functions: the original MPM (Thesis eq. 2.8-2.23, 4.6-4.7).
#pragma once
#include <cmath>

#include "core/inline.hpp"
#include "shape/separable.hpp"

namespace skred {

// 1D linear weights for a point at xi (cell units, measured from the low wall). Returns the
// padded index of the first of the two nodes.
SKRED_INLINE int linear_1d(double xi, int cells, double inv_h, double* w, double* g) {
  int c = static_cast<int>(std::floor(xi));
  if (c == cells) c = cells - 1;  // a point exactly on the high wall belongs to the last cell
  const double f = xi - c;
  w[0] = 1.0 - f;
  w[1] = f;
  g[0] = -inv_h;
  g[1] = inv_h;
  return c + GridGeometry<1>::pad;
}

// Stored without w[0] = 1 - f, as linear_1d computes it.
template <int D>
struct LinearKernel : SeparableKernel<LinearKernel<D>, D, 2, 0> {
  static constexpr int S = 2;
  using typename SeparableKernel<LinearKernel<D>, D, 2, 0>::Shape;
  static constexpr const char* name = "linear";

  SKRED_INLINE bool shape(const GridGeometry<D>& g, const Vec<D>& x, const Vec<D>& /*half0*/,
                          const Mat<D>& /*F*/, Shape& sh) const {
    std::array<int, D> start{};
    const double inv_h = 1.0 / g.h;
    for (int d = 0; d < D; ++d)
      start[d] = linear_1d((x[d] - g.origin[d]) * inv_h, g.cells[d], inv_h, sh.w[d], sh.g[d]);
    return block_base<D, S>(g, start, sh.base);
  }
};

}  // namespace skred
