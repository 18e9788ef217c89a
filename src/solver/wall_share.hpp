// The walls' share of the lumped mass's loss in the particle update, the points' half
// (docs/method.md, "The walls' share of the lumped mass's loss"); the nodes' half is summed in
// Boundaries::constrain_end_of_step. Included by explicit_solver_impl.hpp.
#pragma once
#include <array>
#include <type_traits>

#include "core/inline.hpp"
#include "core/types.hpp"
#include "shape/separable.hpp"
#include "solver/explicit_solver.hpp"

namespace skred {

// The walls' share of the lumped mass's loss in the particle update (eq. 2.56 with the lumped
// m_i = sum_p N_ip m_p, eq. 2.53), USF. The nodal forces' work over the velocity the points move
// with, (v_i^k + v_i^{k+1}) / 2, is dt sum_i a_i . p_i + (1/2) dt^2 sum_i m_i |a_i|^2; the points'
// kinetic energy with the transfer's booked loss (particle_velocity) changes by dt sum_i a_i . p_i
// + (1/2) dt^2 sum_p m_p |acc_p|^2 under FLIP and APIC (acc_p = sum_i N_ip a_i; by Jensen, less).
// The difference is second order in dt where the motion is smooth, and there the step's other
// second-order terms (the stress updated from v^k while the points move with the mean velocity)
// offset it: booked everywhere, it overstated the losses by 1-3 %. Where a wall stops a node within
// one step (dt a_i = -v_i) it is whole, and uncounted it made a column on a fixed base miss 3 % of
// its gravity work. So the walls' part is booked: with s_i the stopped part of a_i (boundary.cpp)
// and s_p = sum_i N_ip s_i, (1/2) dt^2 (sum_i m_i |a_i|^2 - sum_p m_p |acc_p|^2) less the same with
// a - s, = (1/2) dt^2 (sum_i m_i s_i . a_i - sum_p m_p s_p . (2 acc_p - s_p)). Under the PIC share
// and XPIC the difference is (1/2) dt (sum_i m_i a_i . v_i^{k+1} - sum_p m_p acc_p . v_p^{k+1}) and
// its walls' part (1/2) dt (sum_i m_i s_i . v_i^{k+1} - sum_p m_p s_p . v_p^{k+1}). The nodes'
// halves are WallEnergy's update_loss_change and update_loss_end; this is a point's, nonzero only
// where its nodes reach a wall (`Boundaries::block_layers`).
template <class Shape, int D>
SKRED_INLINE double wall_update_loss(const Shape& sh, const NodeStrides<D>& strides,
                                     const Vec<D>* __restrict stopped,
                                     const std::type_identity_t<std::array<unsigned, D>>& layers, double dt,
                                     double m, bool from_flip, const Vec<D>& acc_p, const Vec<D>& v_new) {
  const Vec<D> s = gather_layers(sh, strides, stopped, layers);  // s_i is zero off the walls
  return -0.5 * dt * m * s.dot(from_flip ? Vec<D>(dt * (2.0 * acc_p - s)) : v_new);
}

// The sides flagged in `stopping` (WallEnergy::stopping) that a point at x is within S h of,
// so that its block of S nodes per axis may hold a node on them (bit 2 axis + 0 low / 1 high;
// Boundaries::block_layers tells).
template <int S, int D>
SKRED_INLINE unsigned near_stopping_sides(double h, const WallBox<D>& walls,
                                          const std::array<bool, 2 * D>& stopping, const Vec<D>& x) {
  unsigned near = 0;
  for (int d = 0; d < D; ++d) {
    if (stopping[2 * d] && x[d] - walls.lo[d] < S * h) near |= 1u << (2 * d);
    if (stopping[2 * d + 1] && walls.hi[d] - x[d] < S * h) near |= 2u << (2 * d);
  }
  return near;
}

}  // namespace skred
