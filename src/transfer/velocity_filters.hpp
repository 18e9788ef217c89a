// Grid-side pieces of the velocity transfers beyond FLIP (src/solver/velocity_transfer.hpp):
// the affine momentum map of APIC and the XPIC(m) nodal velocity.
#pragma once
#include <omp.h>

#include "core/inline.hpp"
#include "core/particles.hpp"
#include "transfer/point_selection.hpp"
#include "transfer/transfer.hpp"

namespace skred {

// APIC (Jiang et al. 2015, eq. 9 with C_p = B_p D_p^-1): p_i += N_ip m_p (v_p + C_p (x_i - x_p)).
// The node positions x_i are the grid's degrees of freedom (Greville abscissae for the
// B-spline).
template <int D, class Shape>
SKRED_INLINE void scatter_affine(const Shape& sh, const GridGeometry<D>& g, const NodeStrides<D>& strides,
                                 const Vec<D>& x, double m, const Vec<D>& v, const Mat<D>& C,
                                 Vec<D>* __restrict mom) {
  const Vec<D> mv = m * v;
  const Mat<D> mC = m * C;
  for_each_node(sh, strides, [&](std::size_t i, double w, const Vec<D>&) {
    mom[i] += w * (mv + mC * (g.node_position(i) - x));
  });
}

// XPIC(m) (Hammerquist & Nairn 2017): the nodal velocity whose interpolation to the points is
// the part of their velocities the grid can represent, v* = sum_{k=0}^{m-1} (I - G)^k v^L,
// with v^L = p_i / m_i (lumped) and G v = M_L^-1 sum_p N_ip m_p sum_j N_jp v_j (a g2p and a
// mass-weighted p2g: G = M_L^-1 M_C, so v* tends to M_C^-1 p as m grows; m = 1 gives v^L, PIC).
// Horner form: v* <- v^L + v* - G v*, m - 1 times, each one pass over the points with their
// stored weighting functions. `work` is a zeroed nodal array, zeroed again on return. `sel`
// picks the points whose fields m, p are (one body's, with contact).
template <int D, class K, class Sel = AllPoints>
void xpic_velocity(Transfer<D>& T, const K& kernel, const Particles<D>& P, const double* mass,
                   const Vec<D>* mom, int order, Vec<D>* star, Vec<D>* work, Sel sel = {}) {
  T.for_box([&](std::size_t i) { star[i] = mass[i] > 0.0 ? Vec<D>(mom[i] / mass[i]) : Vec<D>::Zero(); });
  const long n = static_cast<long>(P.size());
  const typename K::Packed* __restrict shape = T.weights().template get<K>(P.size());
  const NodeStrides<D> strides = T.strides();
  ScatterBuffers<D>& S = T.scatter();
  for (int k = 1; k < order; ++k) {
#pragma omp parallel num_threads(T.threads())
    {
      const int t = omp_get_thread_num();
      Vec<D>* __restrict out = S.vec_target(t, work);
      BaseSpan span;
#pragma omp for schedule(static) nowait
      for (long q = 0; q < n; ++q) {
        if (!sel(q)) continue;
        typename K::Shape sh;
        kernel.load(shape[q], T.grid(), P.x[q], P.half0[q], sh);
        scatter(sh, strides, Vec<D>(P.mass[q] * gather(sh, strides, star)), out);
        span.add(sh.base);
      }
      S.touched(t, span);
    }
    T.reduce(nullptr, work);
    T.for_box([&](std::size_t i) {
      const double m = mass[i];
      star[i] = m > 0.0 ? Vec<D>((mom[i] + m * star[i] - work[i]) / m) : Vec<D>::Zero();
      work[i].setZero();
    });
  }
}

}  // namespace skred
