// The grid phases of the time step (Thesis eq. 2.23, 2.49, 2.52, 5.8-5.11) and the reduction
// of the per-thread scatter buffers. They run over the box of nodes the points can reach.
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "solver/explicit_solver.hpp"

namespace skred {

template <int D> void ExplicitSolver<D>::reduce_scatter(bool mass, GridArray<Vec<D>>& target) {
  const std::size_t layer = grid_.stride(D - 1);  // nodes per index of the last axis
  for (auto& b : buffers_) {
    if (b.lo > b.hi) continue;
    // The part of the box the buffer's blocks reach along the last axis.
    const int first = static_cast<int>(b.lo / layer);
    const int last = static_cast<int>(b.hi / layer) + kMaxStencil - 1;
    double* __restrict m = fields_.mass.data();
    double* __restrict bm = b.mass.data();
    Vec<D>* __restrict f = target.data();
    Vec<D>* __restrict bv = b.vec.data();
    for_box(
        [&](std::size_t i) {
          if (mass) {
            m[i] += bm[i];
            bm[i] = 0.0;
          }
          f[i] += bv[i];
          bv[i].setZero();
        },
        first, last);
    b.lo = SIZE_MAX;
    b.hi = 0;
  }
}

// The grid phases run over the box of nodes that the points' stencils can reach: per axis
// from the lowest to the highest point, widened by the stencil width plus one. Outside it the
// mass, momentum and scatter buffers are zero and nothing else is read.
template <int D> void ExplicitSolver<D>::set_box(const Vec<D>& lo, const Vec<D>& hi) {
  for (int d = 0; d < D; ++d) {
    if (!(lo[d] <= hi[d])) {  // no points
      box_.lo[d] = 0;
      box_.hi[d] = -1;
      continue;
    }
    const double inv_h = 1.0 / grid_.h, reach = kMaxStencil + 1;
    const double a = std::floor((lo[d] - grid_.origin[d]) * inv_h) + GridGeometry<D>::pad - reach;
    const double b = std::floor((hi[d] - grid_.origin[d]) * inv_h) + GridGeometry<D>::pad + reach;
    box_.lo[d] = static_cast<int>(std::clamp(a, 0.0, grid_.nodes(d) - 1.0));
    box_.hi[d] = static_cast<int>(std::clamp(b, 0.0, grid_.nodes(d) - 1.0));
  }
}

// Thesis eq. 2.23: v_i = (m_i v_i) / m_i, then the velocity boundary conditions. With clear,
// the mass and momentum are zeroed behind, ready for the map at the end of the step.
template <int D> void ExplicitSolver<D>::nodal_velocity(GridArray<Vec<D>>& velocity, bool clear) {
  double* __restrict mass = fields_.mass.data();
  Vec<D>* __restrict mom = fields_.momentum.data();
  Vec<D>* __restrict vel = velocity.data();
  for_box([&](std::size_t i) {
    const double m = mass[i];
    vel[i] = m > 0.0 ? Vec<D>(mom[i] / m) : Vec<D>::Zero();
    if (clear) {
      mass[i] = 0.0;
      mom[i].setZero();
    }
  });
  boundaries_.constrain_velocity(velocity);
}

template <int D> void ExplicitSolver<D>::clear_mass_momentum() {
  for_box([&](std::size_t i) {
    fields_.mass[i] = 0.0;
    fields_.momentum[i].setZero();
  });
}

// Thesis eq. 2.49 with lumped mass: a_i = (f_i^int + m_i g) / m_i (eq. 2.52 with uniform
// gravity); the particles move with v_i + dt/2 a_i (eq. 2.55, Post eq. 31). Then the
// boundary conditions, including friction (eq. 5.8-5.11), on the wall nodes.
template <int D> void ExplicitSolver<D>::update_grid() {
  const Vec<D> g = gravity_now_;
  const double dt = settings_.dt, half_dt = 0.5 * dt;
  for_box([&](std::size_t i) {
    const double m = fields_.mass[i];
    const Vec<D> a = m > 0.0 ? Vec<D>(fields_.accel[i] / m + g) : Vec<D>::Zero();  // f_i -> a_i
    fields_.accel[i] = a;
    fields_.velocity_move[i] = fields_.velocity[i] + half_dt * a;
  });
  boundaries_.constrain_end_of_step(fields_, dt);
  if (settings_.pic_fraction > 0.0) {  // v_i^{k+1} for the PIC part of the particle update
    for_box([&](std::size_t i) {
      const double m = fields_.mass[i];
      fields_.velocity[i] = m > 0.0 ? Vec<D>(fields_.momentum[i] / m + dt * fields_.accel[i])
                                    : Vec<D>::Zero();
    });
  }
}

#define SKRED_GRID_PHASES(D)                                                                  \
  template void ExplicitSolver<D>::reduce_scatter(bool, GridArray<Vec<D>>&);                  \
  template void ExplicitSolver<D>::set_box(const Vec<D>&, const Vec<D>&);\
  template void ExplicitSolver<D>::nodal_velocity(GridArray<Vec<D>>&, bool);                  \
  template void ExplicitSolver<D>::clear_mass_momentum();                                     \
  template void ExplicitSolver<D>::update_grid();
SKRED_GRID_PHASES(2)
SKRED_GRID_PHASES(3)
#undef SKRED_GRID_PHASES

}  // namespace skred
