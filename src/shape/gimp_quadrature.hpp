// GIMP integrated by Gauss quadrature over the deformed voxel (Thesis §3.3.1, eq. 3.16-3.22;
// Paper III eq. C.17-C.23). Gauss points sit at x_GP = x_p + F dx^0 (eq. 3.20-3.22), and
// the weighting function is the weighted mean of linear shape functions at the Gauss points
// (eq. 3.18-3.19). Q = 1, 2 or 3 points per direction.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/inline.hpp"
#include "shape/linear.hpp"
#include "shape/separable.hpp"

namespace skred {

template <int Q>
struct GaussLegendre;
template <>
struct GaussLegendre<1> {
  static constexpr double x[1] = {0.0};
  static constexpr double w[1] = {2.0};
};
template <>
struct GaussLegendre<2> {
  static constexpr double x[2] = {-0.57735026918962576451, 0.57735026918962576451};
  static constexpr double w[2] = {1.0, 1.0};
};
template <>
struct GaussLegendre<3> {
  static constexpr double x[3] = {-0.77459666924148337704, 0.0, 0.77459666924148337704};
  static constexpr double w[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
};

// Not separable: between the phases of a step the solver keeps the start-of-step F and
// evaluates the stencil again (x_p does not change before the end of the step).
template <int D>
struct QuadratureState {
  Mat<D> F;
};

template <int D, int Q>
struct GimpQuadratureKernel {
  // A Gauss point's two nodes per axis must lie in a block of four: the deformed voxel may
  // span at most three cells per axis.
  static constexpr int S = 4;
  static constexpr int NGP = ipow(Q, D);
  using StencilT = Stencil<D, S>;
  using Shape = StencilT;
  using Packed = QuadratureState<D>;
  static constexpr const char* name = "gimp-quadrature";

  void store(Packed& p, const Shape& /*sh*/, const Mat<D>& F) const { p.F = F; }
  SKRED_INLINE void load(const Packed& p, const GridGeometry<D>& g, const Vec<D>& x, const Vec<D>& half0,
                         Shape& sh) const {
    shape(g, x, half0, p.F, sh);
  }
  bool operator()(const GridGeometry<D>& g, const Vec<D>& x, const Vec<D>& half0, const Mat<D>& F,
                  StencilT& st) const {
    return shape(g, x, half0, F, st);
  }

  SKRED_INLINE bool shape(const GridGeometry<D>& g, const Vec<D>& x, const Vec<D>& half0, const Mat<D>& F,
                          StencilT& st) const {
    const double inv_h = 1.0 / g.h;
    // Gauss point positions (in cell units) and their normalised weights (sum 1).
    Vec<D> xi_gp[NGP];
    double wt[NGP];
    std::array<int, D> lo, hi;
    lo.fill(1 << 30);
    hi.fill(-(1 << 30));
    for (int k = 0; k < NGP; ++k) {
      Vec<D> dx0;
      double wk = 1.0;
      int r = k;
      for (int d = 0; d < D; ++d) {
        dx0[d] = half0[d] * GaussLegendre<Q>::x[r % Q];
        wk *= 0.5 * GaussLegendre<Q>::w[r % Q];
        r /= Q;
      }
      const Vec<D> xg = x + F * dx0;  // eq. 3.21-3.22
      wt[k] = wk;
      for (int d = 0; d < D; ++d) {
        xi_gp[k][d] = (xg[d] - g.origin[d]) * inv_h;
        int c = static_cast<int>(std::floor(xi_gp[k][d]));
        if (c == g.cells[d]) c = g.cells[d] - 1;
        lo[d] = std::min(lo[d], c);
        hi[d] = std::max(hi[d], c);
      }
    }
    // A voxel drawn out over more than three cells along an axis (a needle) has its Gauss
    // points drawn in towards x_p along it until they span less than two cells, as GIMP caps
    // its half-length (gimp.hpp): the weights keep their sum and first moment (the points are
    // symmetric about x_p), and a needle does not stop the run.
    for (int d = 0; d < D; ++d) {
      double a = xi_gp[0][d], b = a;  // (the cells of lo, hi are clamped at the high wall)
      for (int k = 1; k < NGP; ++k) a = std::min(a, xi_gp[k][d]), b = std::max(b, xi_gp[k][d]);
      if (std::floor(b) - std::floor(a) <= S - 2) continue;
      const double xc = (x[d] - g.origin[d]) * inv_h;
      double reach = 0.0;
      for (int k = 0; k < NGP; ++k) reach = std::max(reach, std::abs(xi_gp[k][d] - xc));
      const double scale = 0.99 / reach;
      lo[d] = 1 << 30;
      hi[d] = -(1 << 30);
      for (int k = 0; k < NGP; ++k) {
        xi_gp[k][d] = xc + (xi_gp[k][d] - xc) * scale;
        int c = static_cast<int>(std::floor(xi_gp[k][d]));
        if (c == g.cells[d]) c = g.cells[d] - 1;
        lo[d] = std::min(lo[d], c);
        hi[d] = std::max(hi[d], c);
      }
    }
    std::array<int, D> start{};
    for (int d = 0; d < D; ++d) {
      // Shift the block inwards at the high wall so it stays inside the grid.
      start[d] = std::clamp(lo[d] + GridGeometry<D>::pad, 0, g.nodes(d) - S);
      if (lo[d] + GridGeometry<D>::pad < start[d] || hi[d] + GridGeometry<D>::pad + 1 > start[d] + S - 1)
        return false;  // outside the grid
    }
    if (!block_base<D, S>(g, start, st.base)) return false;
    st.w.fill(0.0);
    for (auto& gr : st.grad) gr.setZero();
    for (int k = 0; k < NGP; ++k) {
      double w1[D][2], g1[D][2];
      int off[D];
      for (int d = 0; d < D; ++d) off[d] = linear_1d(xi_gp[k][d], g.cells[d], inv_h, w1[d], g1[d]) - start[d];
      // Accumulate the Gauss point's 2^D linear weights into the block (eq. 3.18-3.19).
      for (int c = 0; c < ipow(2, D); ++c) {
        int idx = 0, mul = 1;
        double wv = wt[k];
        Vec<D> gv = Vec<D>::Constant(wt[k]);
        for (int d = 0; d < D; ++d) {
          const int a = (c >> d) & 1;
          idx += (off[d] + a) * mul;
          mul *= S;
          wv *= w1[d][a];
          for (int e = 0; e < D; ++e) gv[e] *= (e == d) ? g1[d][a] : w1[d][a];
        }
        st.w[idx] += wv;
        st.grad[idx] += gv;
      }
    }
    return true;
  }
};

}  // namespace skred
