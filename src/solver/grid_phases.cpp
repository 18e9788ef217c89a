// The grid phases of the explicit step (grid_phases.hpp), and the solver's calls of them for
// each continuum, with what it books from them. They run over the box of nodes the points can
// reach (transfer/node_box.hpp).
#include "solver/grid_phases.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "solver/explicit_solver.hpp"

namespace skred {

namespace {

// With contact: whether more than one continuum has mass at node i (an interface node, where
// the contact phase changes the velocities after the grid update).
template <int D>
bool shared_node(const std::vector<BodyFields<D>>* bodies, std::size_t i) {
  if (!bodies) return false;
  int present = 0;
  for (const BodyFields<D>& b : *bodies) present += b.mass[i] > 0.0;
  return present > 1;
}

// The first loop of grid_update with the local (non-viscous) damping of an equilibrium stage
// (Cundall type, as geotechnical codes offer it): per component, the unbalanced force f_i =
// f_i^int + m_i g gets f_i^damp = -alpha |f_i| sign(v_i^k), opposed to the nodal velocity and
// proportional to the force that is not in equilibrium, so it vanishes at rest and never
// drives a node. Its share of a_i is kept in damping_acceleration; its work is booked where the
// points take their velocity change (ExplicitSolver::damping_work_at_points).
template <int D>
void damped_accelerations(const GridStep<D>& s, GridFields<D>& f) {
  if (f.damping_acceleration.size() != f.size()) f.damping_acceleration.resize(f.size());
  const Vec<D> g = s.gravity;
  const double alpha = s.local_damping, half_dt = 0.5 * s.dt;
  for_box(s.grid, s.box, s.threads, [&](std::size_t i) {
    const double m = f.mass[i];
    const Vec<D>& v = f.velocity[i];
    Vec<D> a = Vec<D>::Zero(), damp = Vec<D>::Zero();
    if (m > 0.0) a = f.acceleration[i] / m + g;
    if (m > 0.0 && !shared_node(s.bodies, i)) {
      for (int d = 0; d < D; ++d)
        damp[d] = v[d] > 0.0 ? -alpha * std::abs(a[d]) : v[d] < 0.0 ? alpha * std::abs(a[d]) : 0.0;
      a += damp;
    }
    f.damping_acceleration[i] = damp;
    f.acceleration[i] = a;
    f.velocity_move[i] = v + half_dt * a;
  });
}

}  // namespace

template <int D>
void nodal_velocity(const GridStep<D>& s, GridFields<D>& f) {
  const double* __restrict mass = f.mass.data();
  const Vec<D>* __restrict mom = f.momentum.data();
  Vec<D>* __restrict vel = f.velocity.data();
  for_box(s.grid, s.box, s.threads, [&](std::size_t i) {
    const double m = mass[i];
    vel[i] = m > 0.0 ? Vec<D>(mom[i] / m) : Vec<D>::Zero();
  });
  s.walls.constrain_velocity(f.velocity, s.box);
}

template <int D>
void remap_velocity(const GridStep<D>& s, GridFields<D>& f) {
  double* __restrict mass = f.mass.data();
  Vec<D>* __restrict mom = f.momentum.data();
  Vec<D>* __restrict remap = f.momentum_remap.data();
  Vec<D>* __restrict vel = f.velocity_remap.data();
  for_box(s.grid, s.box, s.threads, [&](std::size_t i) {
    const double m = mass[i];
    vel[i] = m > 0.0 ? Vec<D>(remap[i] / m) : Vec<D>::Zero();
    mass[i] = 0.0;
    mom[i].setZero();
    remap[i].setZero();
  });
  s.walls.constrain_velocity(f.velocity_remap, s.box);
}

template <int D>
void clear_mass_momentum(const GridStep<D>& s, GridFields<D>& f) {
  for_box(s.grid, s.box, s.threads, [&](std::size_t i) {
    f.mass[i] = 0.0;
    f.momentum[i].setZero();
  });
}

template <int D>
WallEnergy grid_update(const GridStep<D>& s, GridFields<D>& f) {
  const Vec<D> g = s.gravity;
  const double dt = s.dt, half_dt = 0.5 * dt;
  if (s.local_damping > 0.0)
    damped_accelerations(s, f);
  else
    for_box(s.grid, s.box, s.threads, [&](std::size_t i) {
      const double m = f.mass[i];
      const Vec<D> a = m > 0.0 ? Vec<D>(f.acceleration[i] / m + g) : Vec<D>::Zero();
      f.acceleration[i] = a;
      f.velocity_move[i] = f.velocity[i] + half_dt * a;
    });
  const WallEnergy walls = s.walls.constrain_end_of_step(f, dt, s.box, s.exchange);
  if (s.form_velocity_next)  // v_i^{k+1} for the PIC share of the particle update, or APIC's
    for_box(s.grid, s.box, s.threads, [&](std::size_t i) {
      const double m = f.mass[i];
      f.velocity_next[i] = m > 0.0 ? Vec<D>(f.momentum[i] / m + dt * f.acceleration[i]) : Vec<D>::Zero();
    });
  return walls;
}

// The solver's grid phases: each continuum's fields through the functions above.

template <int D>
GridStep<D> ExplicitSolver<D>::grid_step() const {
  return {grid(),
          transfer_.box(),
          threads(),
          boundaries_,
          gravity_now_,
          settings_.dt,
          local_damping_,
          transfer_rule_.forms_velocity_next(),
          contact_on() ? &bodies_ : nullptr,
          transfer_.exchange()};
}

template <int D>
void ExplicitSolver<D>::nodal_velocity() {
  timer_.time(Phase::NodalVelocity, [&] {
    if (contact_on()) return body_nodal_velocity();  // each body its own (contact.cpp)
    skred::nodal_velocity(grid_step(), fields_);
  });
}

template <int D>
void ExplicitSolver<D>::remap_velocity() {
  timer_.time(Phase::RemapVelocity, [&] {
    if (contact_on()) return body_remap_velocity();  // each body its own (contact.cpp)
    skred::remap_velocity(grid_step(), fields_);
  });
}

template <int D>
void ExplicitSolver<D>::clear_mass_momentum() {
  skred::clear_mass_momentum(grid_step(), fields_);
}

// What the walls took is friction work (EnergyTotals).
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
// body's with contact), and the walls' work booked.
template <int D>
void ExplicitSolver<D>::continuum_grid_update(GridFields<D>& f) {
  const WallEnergy walls = skred::grid_update(grid_step(), f);
  EnergyTotals& e = state_.clock.energy;
  e.friction_work += walls.work;
  wall_step_.work += walls.work;
  wall_step_.work_sum += walls.work_sum;
  wall_step_.rule_dissipation += walls.rule_dissipation;
  // USF: the walls' share of the lumped mass's loss, its nodal half (the points': wall_update_loss)
  if (transfer_rule_.walls_share_at_nodes())
    e.transfer_dissipation +=
        transfer_rule_.update_from_flip() ? walls.update_loss_change : walls.update_loss_end;
  for (int side = 0; side < 2 * D; ++side)
    stopping_walls_[side] = stopping_walls_[side] || walls.stopping[side];
}

#define SKRED_GRID_PHASES(D)                                             \
  template void nodal_velocity(const GridStep<D>&, GridFields<D>&);      \
  template void remap_velocity(const GridStep<D>&, GridFields<D>&);      \
  template void clear_mass_momentum(const GridStep<D>&, GridFields<D>&); \
  template WallEnergy grid_update(const GridStep<D>&, GridFields<D>&);   \
  template GridStep<D> ExplicitSolver<D>::grid_step() const;             \
  template void ExplicitSolver<D>::nodal_velocity();                     \
  template void ExplicitSolver<D>::remap_velocity();                     \
  template void ExplicitSolver<D>::clear_mass_momentum();                \
  template void ExplicitSolver<D>::grid_update();                        \
  template void ExplicitSolver<D>::continuum_grid_update(GridFields<D>&);
SKRED_GRID_PHASES(2)
SKRED_GRID_PHASES(3)
#undef SKRED_GRID_PHASES

}  // namespace skred
