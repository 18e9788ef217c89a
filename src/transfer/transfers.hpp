// Particle-to-grid (p2g) and grid-to-particle (g2p) maps over (particle arrays, stored
// weights, grid arrays), parallel and lock-free. The explicit phases fuse some of them point
// by point (map_point below); the whole-array forms serve everything else (the start of a
// run, per-body fields for contact, the momentum remap of USL and the averaged scheme).
#pragma once
#include <omp.h>

#include <type_traits>

#include <climits>
#include <cstdint>

#include "core/inline.hpp"
#include "core/particles.hpp"
#include "transfer/point_selection.hpp"
#include "transfer/transfer.hpp"
#include "transfer/velocity_filters.hpp"

namespace skred {

// Thesis eq. 2.53-2.54 for one point: its weighting functions are evaluated, stored for the
// rest of the step, and its mass and momentum mapped to the nodes (with an affine velocity C,
// if given: APIC; then `affine_energy`, if given, gains 1/2 m sum_i N_ip |C (x_i - x_p)|^2). False if
// the point's stencil does not fit in the grid.
// `size` is the point's (x-independent) part of the weights, if the kernel has one
// (SizedKernel: GIMP's half-lengths, eq. 3.23), else its initial half-lengths half0.
template <int D, class K, class Size>
SKRED_INLINE bool map_point(const K& kernel, const GridGeometry<D>& grid, const NodeStrides<D>& strides,
                            const Vec<D>& x, const Size& size, const Mat<D>& F, double m, const Vec<D>& v,
                            typename K::Packed& store, double* __restrict mass, Vec<D>* __restrict mom,
                            BaseSpan& span, const Mat<D>* C = nullptr, double* affine_energy = nullptr) {
  typename K::Shape sh;
  if constexpr (std::is_same_v<Size, Vec<D>>) {
    if (!kernel.shape(grid, x, size, F, sh)) return false;
  } else {
    if (!kernel.shape(grid, x, size, sh)) return false;
  }
  kernel.store(store, sh, F);
  span.add(sh.base);
  scatter(sh, strides, m, mass);
  if (C)
    scatter_affine(sh, grid, strides, x, m, v, *C, mom, affine_energy);
  else
    scatter(sh, strides, Vec<D>(m * v), mom);
  return true;
}

// m_i = sum_p N_ip m_p and p_i = sum_p N_ip m_p v_p (eq. 2.53-2.54) into zeroed arrays m, p,
// evaluating and storing every point's weighting functions and setting the box from the
// points' extent (with the points' affine velocities, if stored: APIC). Returns the first
// point whose stencil leaves the grid, or -1.
template <int D, class K>
long p2g_mass_momentum(Transfer<D>& T, const K& kernel, const Particles<D>& P, double* m, Vec<D>* p) {
  const Mat<D>* affine = P.affine.size() == P.size() ? P.affine.data() : nullptr;
  const long n = static_cast<long>(P.size());
  const GridGeometry<D>& grid = T.grid();
  const NodeStrides<D> strides = T.strides();
  typename K::Packed* __restrict shape = T.weights().template get<K>(P.size());
  const Vec<D>* __restrict x = P.x.data();
  const Vec<D>* __restrict v = P.v.data();
  const Vec<D>* __restrict half0 = P.half0.data();
  const Mat<D>* __restrict F = P.F.data();
  const double* __restrict pmass = P.mass.data();
  long bad = LONG_MAX;
  Extent<D> extent;
  ScatterBuffers<D>& S = T.scatter();
#pragma omp parallel num_threads(T.threads()) reduction(min : bad) reduction(merge : extent)
  {
    const int t = omp_get_thread_num();
    double* __restrict mass = S.mass_target(t, m);
    Vec<D>* __restrict mom = S.vec_target(t, p);
    BaseSpan span;
#pragma omp for schedule(static) nowait
    for (long q = 0; q < n; ++q) {
      if (!map_point(kernel, grid, strides, x[q], half0[q], F[q], pmass[q], v[q], shape[q], mass, mom, span,
                     affine ? affine + q : nullptr))
        bad = std::min(bad, q);
      extent.add(x[q]);
    }
    S.touched(t, span);
  }
  T.set_box(extent);
  T.reduce(m, p);
  return bad == LONG_MAX ? -1 : bad;
}

// The same maps restricted to the points of one body (continuum, Paper III §C.2.7): m_i^b and
// p_i^b into zeroed arrays. The weighting functions are evaluated as p2g_mass_momentum does
// (not loaded from the stored ones, which can differ in the last bit), so that this map equals
// the per-body map that ends a step with contact bit for bit.
template <int D, class K>
void p2g_body_mass_momentum(Transfer<D>& T, const K& kernel, const Particles<D>& P, int body, double* m,
                            Vec<D>* p) {
  const long n = static_cast<long>(P.size());
  ScatterBuffers<D>& S = T.scatter();
#pragma omp parallel num_threads(T.threads())
  {
    const int t = omp_get_thread_num();
    double* __restrict mass = S.mass_target(t, m);
    Vec<D>* __restrict mom = S.vec_target(t, p);
    BaseSpan span;
#pragma omp for schedule(static) nowait
    for (long q = 0; q < n; ++q) {
      if (P.body[q] != body) continue;
      typename K::Shape sh;
      if (!kernel.shape(T.grid(), P.x[q], P.half0[q], P.F[q], sh)) continue;  // reported by the map
      span.add(sh.base);
      scatter(sh, T.strides(), P.mass[q], mass);
      if (P.affine.size() == P.size())
        scatter_affine(sh, T.grid(), T.strides(), P.x[q], P.mass[q], P.v[q], P.affine[q], mom);
      else
        scatter(sh, T.strides(), Vec<D>(P.mass[q] * P.v[q]), mom);
    }
    S.touched(t, span);
  }
  T.reduce(m, p);
}

// No shift of the stresses' diagonal in p2g_internal_force.
struct NoPressureShift {};

// f_i^int = -sum_p sigma_p V_p grad N_ip (eq. 2.51) from the points' current stresses (of
// the points `sel` selects), into a zeroed array f; with `shift`, sigma_p + shift(q) I (the cell
// pressure of solver/volumetric_averaging.hpp). Axisymmetric (2D, x the radius; Acosta App. A1
// eq. 30): also -V_p sigma_theta N_ip / r_p on the radial component.
template <int D, class K, class Sel = AllPoints, class Shift = NoPressureShift>
void p2g_internal_force(Transfer<D>& T, const K& kernel, const Particles<D>& P, Vec<D>* f, Sel sel = {},
                        Shift shift = {}, [[maybe_unused]] bool axisymmetric = false) {
  const long n = static_cast<long>(P.size());
  const typename K::Packed* __restrict shape = T.weights().template get<K>(P.size());
  ScatterBuffers<D>& S = T.scatter();
#pragma omp parallel num_threads(T.threads())
  {
    const int t = omp_get_thread_num();
    Vec<D>* __restrict force = S.vec_target(t, f);
    BaseSpan span;
#pragma omp for schedule(static) nowait
    for (long q = 0; q < n; ++q) {
      if (!sel(q)) continue;
      typename K::Shape sh;
      kernel.load(shape[q], T.grid(), P.x[q], P.half0[q], sh);
      Mat<D> sigma = sym_block<D>(P.stress[q]);
      double s_shift = 0.0;
      if constexpr (!std::is_same_v<Shift, NoPressureShift>) {
        s_shift = shift(q);
        sigma.diagonal().array() += s_shift;
      }
      const double V = P.volume(static_cast<std::size_t>(q));
      const Mat<D> sv = -V * sigma;
      scatter_gradient(sh, T.strides(), sv, force);
      if constexpr (D == 2)
        if (axisymmetric)
          scatter(sh, T.strides(), Vec<D>(-V * (P.stress[q][2] + s_shift) / P.x[q][0], 0.0), force);
      span.add(sh.base);
    }
    S.touched(t, span);
  }
  T.reduce(nullptr, f);
}

// fn(q, shape) for every point q with its weighting functions stored by the last
// p2g_mass_momentum, in parallel.
template <int D, class K, class Fn>
void for_each_stored_shape(Transfer<D>& T, const K& kernel, const Particles<D>& P, Fn&& fn) {
  const long n = static_cast<long>(P.size());
  const typename K::Packed* __restrict shape = T.weights().template get<K>(P.size());
#pragma omp parallel for num_threads(T.threads()) schedule(static)
  for (long q = 0; q < n; ++q) {
    typename K::Shape sh;
    kernel.load(shape[q], T.grid(), P.x[q], P.half0[q], sh);
    fn(q, sh);
  }
}

// out_p = sum_i N_ip v_i (eq. 2.56 with a nodal field v).
template <int D, class K>
void g2p_velocity(Transfer<D>& T, const K& kernel, const Particles<D>& P, const Vec<D>* v, Vec<D>* out) {
  for_each_stored_shape(T, kernel, P, [&](long q, const auto& sh) { out[q] = gather(sh, T.strides(), v); });
}

// out_p = sum_i v_i (x) grad N_ip: the velocity gradient of eq. 2.20.
template <int D, class K>
void g2p_velocity_gradient(Transfer<D>& T, const K& kernel, const Particles<D>& P, const Vec<D>* v,
                           Mat<D>* out) {
  for_each_stored_shape(T, kernel, P,
                        [&](long q, const auto& sh) { out[q] = gather_gradient(sh, T.strides(), v); });
}

}  // namespace skred
