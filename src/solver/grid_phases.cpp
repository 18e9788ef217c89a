// The grid phases of the time step (Thesis eq. 2.23, 2.49, 2.52, 5.8-5.11). They run over
// the box of nodes the points can reach (transfer/node_box.hpp).
#include <omp.h>

#include <algorithm>
#include <cassert>
#include <cmath>

#include "solver/explicit_solver.hpp"

namespace skred {

// Thesis eq. 2.23: v_i^k = p_i / m_i, then the velocity boundary conditions.
template <int D>
void ExplicitSolver<D>::nodal_velocity() {
  timer_.time(Phase::NodalVelocity, [&] {
    if (contact_on()) return body_nodal_velocity();  // each body its own (contact.cpp)
    const double* __restrict mass = fields_.mass.data();
    const Vec<D>* __restrict mom = fields_.momentum.data();
    Vec<D>* __restrict vel = fields_.velocity.data();
    transfer_.for_box([&](std::size_t i) {
      const double m = mass[i];
      vel[i] = m > 0.0 ? Vec<D>(mom[i] / m) : Vec<D>::Zero();
    });
    boundaries_.constrain_velocity(fields_.velocity, transfer_.box());
  });
}

// v~_i = p~_i / m_i from the momentum remap (USL, averaged), under the velocity boundary
// conditions. m_i, p_i and p~_i are used up: they are cleared behind, ready for the next
// step's map.
template <int D>
void ExplicitSolver<D>::remap_velocity() {
  timer_.time(Phase::RemapVelocity, [&] {
    if (contact_on()) return body_remap_velocity();  // each body its own (contact.cpp)
    double* __restrict mass = fields_.mass.data();
    Vec<D>* __restrict mom = fields_.momentum.data();
    Vec<D>* __restrict remap = fields_.momentum_remap.data();
    Vec<D>* __restrict vel = fields_.velocity_remap.data();
    transfer_.for_box([&](std::size_t i) {
      const double m = mass[i];
      vel[i] = m > 0.0 ? Vec<D>(remap[i] / m) : Vec<D>::Zero();
      mass[i] = 0.0;
      mom[i].setZero();
      remap[i].setZero();
    });
    boundaries_.constrain_velocity(fields_.velocity_remap, transfer_.box());
  });
}

template <int D>
void ExplicitSolver<D>::clear_mass_momentum() {
  transfer_.for_box([&](std::size_t i) {
    fields_.mass[i] = 0.0;
    fields_.momentum[i].setZero();
  });
}

// Thesis eq. 2.49 with lumped mass: a_i = (f_i^int + f_i^ext) / m_i with f_i^ext = m_i g
// (eq. 2.52, uniform gravity); the particles move with v_i + dt/2 a_i (eq. 2.55, Post eq.
// 31). Then the boundary conditions, including friction (eq. 5.8-5.11), on the wall nodes.
// What the walls take is friction work (EnergyTotals).
template <int D>
void ExplicitSolver<D>::grid_update() {
  timer_.time(Phase::GridUpdate, [&] {
    stopping_walls_ = {};  // gathered over the continua (continuum_grid_update)
    wall_step_ = {};
    if (contact_on()) return body_grid_update();  // each body its own (contact.cpp)
    continuum_grid_update(fields_);
  });
}

// The grid update of one continuum's fields f (the centre-of-mass fields, or one deformable
// body's with contact): a_i, v_move, the walls and their friction work, and v_i^{k+1} where
// the velocity transfer takes it.
template <int D>
void ExplicitSolver<D>::continuum_grid_update(GridFields<D>& f) {
  const Vec<D> g = gravity_now_;
  const double dt = settings_.dt, half_dt = 0.5 * dt;
  if (local_damping_ > 0.0)
    damped_accelerations(f);
  else
    transfer_.for_box([&](std::size_t i) {
      const double m = f.mass[i];
      const Vec<D> a = m > 0.0 ? Vec<D>(f.acceleration[i] / m + g) : Vec<D>::Zero();
      f.acceleration[i] = a;
      f.velocity_move[i] = f.velocity[i] + half_dt * a;
    });
  const WallEnergy walls = boundaries_.constrain_end_of_step(f, dt, transfer_.box());
  energy_.friction_work += walls.work;
  wall_step_.work += walls.work;
  wall_step_.work_sum += walls.work_sum;
  wall_step_.rule_dissipation += walls.rule_dissipation;
  // USF: the walls' share of the lumped mass's loss, its nodal half (the points': wall_update_loss)
  if (transfer_rule_.walls_share_at_nodes())
    energy_.transfer_dissipation +=
        transfer_rule_.update_from_flip() ? walls.update_loss_change : walls.update_loss_end;
  for (int side = 0; side < 2 * D; ++side)
    stopping_walls_[side] = stopping_walls_[side] || walls.stopping[side];
  if (transfer_rule_.forms_velocity_next())  // v_i^{k+1} for the PIC share of the particle update, or APIC's
    transfer_.for_box([&](std::size_t i) {
      const double m = f.mass[i];
      f.velocity_next[i] = m > 0.0 ? Vec<D>(f.momentum[i] / m + dt * f.acceleration[i]) : Vec<D>::Zero();
    });
}

// The first loop of grid_update with the local (non-viscous) damping of an equilibrium stage
// (Cundall type, as geotechnical codes offer it): per component, the unbalanced force f_i =
// f_i^int + m_i g gets f_i^damp = -alpha |f_i| sign(v_i^k), opposed to the nodal velocity and
// proportional to the force that is not in equilibrium, so it vanishes at rest and never
// drives a node. Its share of a_i is kept in damping_acceleration; its work is booked where the
// points take their velocity change (damping_work_at_points).
template <int D>
void ExplicitSolver<D>::damped_accelerations(GridFields<D>& f) {
  if (f.damping_acceleration.size() != f.size()) f.damping_acceleration.resize(f.size());
  const Vec<D> g = gravity_now_;
  const double alpha = local_damping_, half_dt = 0.5 * settings_.dt;
  transfer_.for_box([&](std::size_t i) {
    const double m = f.mass[i];
    const Vec<D>& v = f.velocity[i];
    Vec<D> a = Vec<D>::Zero(), damp = Vec<D>::Zero();
    if (m > 0.0) a = f.acceleration[i] / m + g;
    if (m > 0.0 && !shared_node(i)) {
      for (int d = 0; d < D; ++d)
        damp[d] = v[d] > 0.0 ? -alpha * std::abs(a[d]) : v[d] < 0.0 ? alpha * std::abs(a[d]) : 0.0;
      a += damp;
    }
    f.damping_acceleration[i] = damp;
    f.acceleration[i] = a;
    f.velocity_move[i] = v + half_dt * a;
  });
}

// With contact: whether more than one continuum has mass at node i (an interface node, where
// the contact phase changes the velocities after the grid update).
template <int D>
bool ExplicitSolver<D>::shared_node(std::size_t i) const {
  if (!contact_on()) return false;
  int present = 0;
  for (const BodyFields<D>& b : bodies_) present += b.mass[i] > 0.0;
  return present > 1;
}

#define SKRED_GRID_PHASES(D)                                             \
  template void ExplicitSolver<D>::nodal_velocity();                     \
  template void ExplicitSolver<D>::remap_velocity();                     \
  template void ExplicitSolver<D>::clear_mass_momentum();                \
  template void ExplicitSolver<D>::grid_update();                        \
  template void ExplicitSolver<D>::damped_accelerations(GridFields<D>&); \
  template bool ExplicitSolver<D>::shared_node(std::size_t) const;
SKRED_GRID_PHASES(2)
SKRED_GRID_PHASES(3)
#undef SKRED_GRID_PHASES

}  // namespace skred
