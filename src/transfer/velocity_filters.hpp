// Grid-side pieces of the velocity transfers beyond FLIP (src/solver/velocity_transfer.hpp):
// the affine momentum map of APIC and the XPIC(m) nodal velocity.
#pragma once
#include <omp.h>

#include "core/inline.hpp"
#include "core/particles.hpp"
#include "transfer/point_selection.hpp"
#include "transfer/transfer.hpp"

namespace skred {

// The kinetic energy of an APIC point is that of its affine velocity field sampled at its
// nodes, 1/2 m_p sum_i N_ip |v_p + C_p (x_i - x_p)|^2 = 1/2 m_p (|v_p|^2 + sum_i N_ip |C_p (x_i -
// x_p)|^2) (the cross term vanishes: sum_i N_ip (x_i - x_p) = 0 for every kernel here). This
// returns sum_i N_ip |C_p (x_i - x_p)|^2.
template <int D, class Shape>
SKRED_INLINE double affine_energy(const Shape& sh, const GridGeometry<D>& g, const NodeStrides<D>& strides,
                                  const Vec<D>& x, const Mat<D>& C) {
  double e = 0.0;
  for_each_node(sh, strides, [&](std::size_t i, double w, const Vec<D>&) {
    e += w * (C * (g.node_position(i) - x)).squaredNorm();
  });
  return e;
}

// For the energy booked as transfer dissipation under APIC: the point's kinetic energy (as
// affine_energy defines it) after a FLIP update by the nodal accelerations a_i, minus
// 1/2 m_p |v_p + dt sum N_ip a_i|^2: 1/2 m_p (2 dt sum_i N_ip (C_p (x_i - x_p)) . a_i +
// sum_i N_ip |C_p (x_i - x_p)|^2) (second order in dt dropped, as FLIP's own measure does).
template <int D, class Shape>
SKRED_INLINE double affine_trial_energy(const Shape& sh, const GridGeometry<D>& g,
                                        const NodeStrides<D>& strides, const Vec<D>& x, const Mat<D>& C,
                                        const Vec<D>* __restrict acc, double dt, double m) {
  double e = 0.0;
  for_each_node(sh, strides, [&](std::size_t i, double w, const Vec<D>&) {
    const Vec<D> Cr = C * (g.node_position(i) - x);
    e += w * (Cr.squaredNorm() + 2.0 * dt * Cr.dot(acc[i]));
  });
  return 0.5 * m * e;
}

// The offsets r_d[a] = X_d(a) - x_d of a separable block's nodes from x along each axis.
template <int D, int S>
SKRED_INLINE void block_offsets(const Separable<D, S>& sh, const GridGeometry<D>& g, const Vec<D>& x,
                                double (&r)[D][S]) {
  const auto ij = g.unflatten(sh.base);
  for (int d = 0; d < D; ++d)
    for (int a = 0; a < S; ++a) r[d][a] = g.origin[d] + g.node_coordinate(d, ij[d] + a) - x[d];
}

// sum_d (sum_a w_d[a] r_d[a]^2) |C e_d|^2 from a separable block's offsets (affine_energy).
template <int D, int S>
SKRED_INLINE double affine_moment(const Separable<D, S>& sh, const double (&r)[D][S], const Mat<D>& C) {
  double e = 0.0;
  for (int d = 0; d < D; ++d) {
    double m2 = 0.0;
    for (int a = 0; a < S; ++a) m2 += sh.w[d][a] * r[d][a] * r[d][a];
    e += m2 * C.col(d).squaredNorm();
  }
  return e;
}

// On a separable block sum_i N_ip r r^T is diagonal (each axis' 1D functions reproduce linear
// fields: sum_a w_d[a] r_d[a] = 0), so sum_i N_ip |C r|^2 = sum_d (sum_a w_d[a] r_d[a]^2) |C e_d|^2.
template <int D, int S>
SKRED_INLINE double affine_energy(const Separable<D, S>& sh, const GridGeometry<D>& g, const NodeStrides<D>&,
                                  const Vec<D>& x, const Mat<D>& C) {
  double r[D][S];
  block_offsets(sh, g, x, r);
  return affine_moment(sh, r, C);
}

// ... and sum_i N_ip a_i (x) r_i is gather_gradient with the 1D derivatives replaced by w_d r_d.
template <int D, int S>
SKRED_INLINE double affine_trial_energy(const Separable<D, S>& sh, const GridGeometry<D>& g,
                                        const NodeStrides<D>& strides, const Vec<D>& x, const Mat<D>& C,
                                        const Vec<D>* __restrict acc, double dt, double m) {
  double r[D][S];
  block_offsets(sh, g, x, r);
  Separable<D, S> moment = sh;
  for (int d = 0; d < D; ++d)
    for (int a = 0; a < S; ++a) moment.g[d][a] = sh.w[d][a] * r[d][a];
  const double e = affine_moment(sh, r, C);
  const Mat<D> B = gather_gradient(moment, strides, acc);  // sum_i N_ip a_i (x) r_i
  return 0.5 * m * (e + 2.0 * dt * C.cwiseProduct(B).sum());
}

// APIC's affine velocity of a point from the new nodal velocities v_i. Jiang et al. (2015) take
// C_p = B_p D_p^-1 with B_p = sum_i N_ip v_i (x_i - x_p)^T and the inertia D_p = sum_i N_ip (x_i -
// x_p)(x_i - x_p)^T (their eq. 8-9), which makes a g2p and p2g round trip keep angular momentum
// exactly for any kernel. For the linear kernel that C_p is the gradient sum_i v_i (x) grad N_ip
// (per axis grad N D = N (x_i - x_p)), and D_p vanishes where a point sits on a node, so the linear
// kernel and GIMP take the gradient form (the choice for them, which also reproduces affine
// fields). A kernel that declares `apic_inertia` (the cubic B-spline, D_p = h^2/3 I away from the
// walls) takes B_p D_p^-1. On a separable block D_p is diagonal (sum_a w_d[a] r_d[a] = 0 per axis),
// and B_p is gather_gradient with the 1D derivatives replaced by w_d r_d (as affine_trial_energy).
template <class K>
inline constexpr bool apic_inertia_v = requires {
  requires K::apic_inertia;
};

template <int D, int S>
SKRED_INLINE Mat<D> affine_from_inertia(const Separable<D, S>& sh, const GridGeometry<D>& g,
                                        const NodeStrides<D>& strides, const Vec<D>& x,
                                        const Vec<D>* __restrict v) {
  double r[D][S];
  block_offsets(sh, g, x, r);
  Separable<D, S> moment = sh;
  double inertia[D];
  for (int d = 0; d < D; ++d) {
    inertia[d] = 0.0;
    for (int a = 0; a < S; ++a) {
      moment.g[d][a] = sh.w[d][a] * r[d][a];
      inertia[d] += sh.w[d][a] * r[d][a] * r[d][a];
    }
  }
  const Mat<D> B = gather_gradient(moment, strides, v);  // sum_i N_ip v_i (x) (x_i - x_p)
  Mat<D> C = B;
  // On a clamped B-spline's wall only the wall's DOF is non-zero and D_p's entry is zero there:
  // that column keeps the gradient form.
  const double tiny = 1e-12 * g.h * g.h;
  bool degenerate = false;
  for (int d = 0; d < D; ++d) degenerate |= !(inertia[d] > tiny);
  const Mat<D> grad = degenerate ? gather_gradient(sh, strides, v) : Mat<D>::Zero();
  for (int d = 0; d < D; ++d)
    C.col(d) = inertia[d] > tiny ? Vec<D>(B.col(d) / inertia[d]) : Vec<D>(grad.col(d));
  return C;
}

template <class K, int D, class Shape>
SKRED_INLINE Mat<D> apic_affine_velocity(const Shape& sh, const GridGeometry<D>& g,
                                         const NodeStrides<D>& strides, const Vec<D>& x,
                                         const Vec<D>* __restrict v) {
  if constexpr (apic_inertia_v<K>)
    return affine_from_inertia(sh, g, strides, x, v);
  else
    return gather_gradient(sh, strides, v);
}

// APIC (Jiang et al. 2015, eq. 9 with C_p = B_p D_p^-1): p_i += N_ip m_p (v_p + C_p (x_i - x_p)).
// The node positions x_i are the grid's degrees of freedom (Greville abscissae for the
// B-spline). With `energy`, it gains 1/2 m_p sum_i N_ip |C_p (x_i - x_p)|^2: the kinetic energy the
// affine velocity adds to the point's (affine_energy).
template <int D, class Shape>
SKRED_INLINE void scatter_affine(const Shape& sh, const GridGeometry<D>& g, const NodeStrides<D>& strides,
                                 const Vec<D>& x, double m, const Vec<D>& v, const Mat<D>& C,
                                 Vec<D>* __restrict mom, double* energy = nullptr) {
  const Vec<D> mv = m * v;
  const Mat<D> mC = m * C;
  for_each_node(sh, strides, [&](std::size_t i, double w, const Vec<D>&) {
    mom[i] += w * (mv + mC * (g.node_position(i) - x));
  });
  if (energy) *energy += 0.5 * m * affine_energy(sh, g, strides, x, C);
}

// The same on a separable block, with the node offsets formed once per axis (block_offsets)
// instead of a node position per node.
template <int D, int S>
SKRED_INLINE void scatter_affine(const Separable<D, S>& sh, const GridGeometry<D>& g,
                                 const NodeStrides<D>& strides, const Vec<D>& x, double m, const Vec<D>& v,
                                 const Mat<D>& C, Vec<D>* __restrict mom, double* energy = nullptr) {
  double r[D][S];
  block_offsets(sh, g, x, r);
  const Vec<D> mv = m * v;
  const Mat<D> mC = m * C;
  if constexpr (D == 2) {
    for (int b = 0; b < S; ++b) {
      Vec<2>* row = mom + sh.base + b * strides.s[1];
      const Vec<2> cy = mv + mC.col(1) * r[1][b];
      for (int a = 0; a < S; ++a) row[a] += (sh.w[0][a] * sh.w[1][b]) * (cy + mC.col(0) * r[0][a]);
    }
  } else {
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b) {
        Vec<3>* row = mom + sh.base + b * strides.s[1] + c * strides.s[2];
        const double wyz = sh.w[1][b] * sh.w[2][c];
        const Vec<3> cyz = mv + mC.col(1) * r[1][b] + mC.col(2) * r[2][c];
        for (int a = 0; a < S; ++a) row[a] += (sh.w[0][a] * wyz) * (cyz + mC.col(0) * r[0][a]);
      }
  }
  if (energy) *energy += 0.5 * m * affine_moment(sh, r, C);
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
