// The kernel-templated phases of a run with contact (Paper III §C.2.7): the rigid bodies'
// points. Included only by explicit_solver_impl.hpp; the grid phases of contact are in
// contact.cpp.
#pragma once
#include <omp.h>

#include <climits>

#include "solver/explicit_solver.hpp"
#include "transfer/transfers.hpp"

namespace skred {

// The rigid bodies' points (contact runs): no stress update; x_p += dt v (only when the body
// moves), then their mass and momentum mapped into their body's fields for the next step
// (their mass gives the contact normal). `all` grows by their extent. Returns the first point
// that left the grid, or LONG_MAX.
template <int D>
template <class K>
long ExplicitSolver<D>::move_and_map_rigid(const K& kernel, Extent<D>& all) {
  const ContactSettings<D>& c = settings_.contact;
  const GridGeometry<D>& g = grid();
  const NodeStrides<D> strides = transfer_.strides();
  auto& P = state_.points;
  const long n = static_cast<long>(P.size());
  const double dt = settings_.dt;
  typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
  ScatterBuffers<D>& buffers = transfer_.scatter();
  long first_bad = LONG_MAX;
  for (int b = 0; b < c.bodies(); ++b) {
    if (!c.rigid[static_cast<std::size_t>(b)]) continue;
    GridFields<D>& f = bodies_[static_cast<std::size_t>(b)];
    const Vec<D> vr = c.rigid_velocity[static_cast<std::size_t>(b)];
    const bool moving = vr.squaredNorm() > 0.0;
    long bad = LONG_MAX;
    Extent<D> extent;
#pragma omp parallel num_threads(threads()) reduction(min : bad) reduction(merge : extent)
    {
      const int t = omp_get_thread_num();
      double* __restrict mass = buffers.mass_target(t, f.mass.data());
      Vec<D>* __restrict mom = buffers.vec_target(t, f.momentum.data());
      BaseSpan span;
#pragma omp for schedule(static) nowait
      for (long p = 0; p < n; ++p) {
        if (P.body[p] != b) continue;
        if (moving) P.x[p] += dt * vr;
        if (!g.inside(P.x[p]) || !map_point(kernel, g, strides, P.x[p], P.half0[p], P.F[p], P.mass[p], vr,
                                            shape[p], mass, mom, span))
          bad = std::min(bad, p);
        extent.add(P.x[p]);
      }
      buffers.touched(t, span);
    }
    transfer_.reduce_threads(extent, f.mass.data(), f.momentum.data());  // (the processes': set_next_box)
    first_bad = std::min(first_bad, bad);
    all.merge(extent);
  }
  return first_bad;
}

// For pairs under the traction rule (ContactDetection::Traction): each deformable body's
// S_i^b = sum_p N_ip m_p sigma_p from its points' stresses as the step starts, its diagonal
// and its off-diagonal part (traction_at) each in a pass of its own (a thread's scatter
// buffer holds one vector field), with the weighting functions of the step. Only the sign
// of n . S . n is used, so S is not divided by m_i^b. Not called for the fill rule.
template <int D>
template <class K>
void ExplicitSolver<D>::map_body_stress(const K& kernel) {
  timer_.time(Phase::BodyFields, [&] {
    const ContactSettings<D>& c = settings_.contact;
    const GridGeometry<D>& g = grid();
    const NodeStrides<D> strides = transfer_.strides();
    const auto& P = state_.points;
    const long n = static_cast<long>(P.size());
    const typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
    ScatterBuffers<D>& buffers = transfer_.scatter();
    for (int b = 0; b < c.bodies(); ++b) {
      if (c.rigid[static_cast<std::size_t>(b)]) continue;  // no stress
      BodyFields<D>& f = bodies_[static_cast<std::size_t>(b)];
      for (const bool diagonal : {true, false}) {
        Vec<D>* const field = diagonal ? f.stress_diagonal.data() : f.stress_off.data();
        transfer_.for_box([&](std::size_t i) { field[i].setZero(); });
#pragma omp parallel num_threads(threads())
        {
          const int t = omp_get_thread_num();
          Vec<D>* __restrict out = buffers.vec_target(t, field);
          BaseSpan span;
#pragma omp for schedule(static) nowait
          for (long p = 0; p < n; ++p) {
            if (P.body[p] != b) continue;
            const Mat<D> s = P.mass[p] * sym_block<D>(P.stress[p]);
            Vec<D> x;
            if (diagonal)
              x = s.diagonal();
            else if constexpr (D == 2)
              x = Vec<D>(s(0, 1), 0.0);
            else
              x = Vec<D>(s(1, 2), s(0, 2), s(0, 1));
            typename K::Shape sh;
            kernel.load(shape[p], g, P.x[p], P.half0[p], sh);
            scatter(sh, strides, x, out);
            span.add(sh.base);
          }
          buffers.touched(t, span);
        }
        transfer_.reduce(nullptr, field);
      }
    }
  });
}

}  // namespace skred
