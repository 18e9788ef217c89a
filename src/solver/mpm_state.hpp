// The state both time integrators advance: the explicit solver (solver/explicit_solver.hpp)
// and the implicit one (src/implicit). It is the material points, the background grid with its
// kernel, the materials of the current stage, and the clock with the energy totals. Each
// integrator adds the fields of its own step (the explicit grid fields and transfer, the implicit
// unknowns and matrix). What both do between steps are functions over this state
// (mpm_state.cpp): the particle totals, the grid-smoothed stresses, the start of a stage and
// the restore of a checkpoint. A distributed run (MPI) would split this state by blocks of
// the grid.
#pragma once
#include <string>
#include <vector>

#include "core/grid.hpp"
#include "core/huge_pages.hpp"
#include "core/particles.hpp"
#include "material/material.hpp"
#include "parallel/processes.hpp"
#include "shape/interpolation.hpp"
#include "solver/gravity.hpp"
#include "solver/implicit_settings.hpp"

namespace skred {

// Running totals kept by an integrator (energy bookkeeping, Thesis eq. 4.15-4.17, 5.13).
struct EnergyTotals {
  double strain_energy = 0.0;  // stored: sum of V (sigma^{k+1} + sigma^k)/2 : (d_eps - d_eps_p) (eq. 4.16)
  double gravity_work = 0.0;   // sum of m_p g . d_x_p (eq. 5.13, incremental form)
  double plastic_dissipation = 0.0;  // plastic work (zero for elastic materials)
  // Work of the contact impulses against the mean relative velocities of each step (Paper
  // III §C.2.7; ContactLoss): friction (>= 0) plus the normal part (small, either sign).
  double contact_work = 0.0;
  // Energy the walls took: Coulomb friction (eq. 5.8-5.11), the no-slip of fixed walls and
  // the motion stopped at every wall; >= 0 at every node and step (boundary.hpp, WallEnergy).
  // (Friction between bodies is in contact_work.)
  double friction_work = 0.0;
  // Kinetic energy the velocity transfer took from the FLIP update (eq. 2.56), per step
  // sum (1/2) m_p (|v_p^FLIP|^2 - |v_p^{k+1}|^2): the PIC share, XPIC and APIC (whose affine
  // velocity's own kinetic energy is not counted in eq. 4.15); zero for pure FLIP.
  double transfer_dissipation = 0.0;
  // Work of the local (Cundall) damping of an equilibrium stage, per step
  // -dt sum_i f_i^damp . (v_i^k + v_i^{k+1}) / 2 (grid_update); zero when it is off.
  double damping_work = 0.0;
  // Work of the boundary pressures (implicit stages, [[pressure]]), per step
  // sum_i (f_i^t + f_i^{t+dt}) / 2 . du_i: energy supplied, like the gravity work.
  double load_work = 0.0;
};

// The clock of a run: time, steps, the gravity ramp of the stage (what begin_stage set) and the
// energy totals; with the points, what a checkpoint keeps and what one integrator hands the next.
struct SolverClock {
  double time = 0.0;
  long steps = 0;
  double ramp_start = 0.0;
  double gravity_ramp_time = 0.0;
  EnergyTotals energy;
  BoundaryForces boundary_force{};  // the prescribed velocities' forces (implicit_settings.hpp)
};

// Quantities summed over the particles on demand.
template <int D>
struct ParticleTotals {
  double mass = 0.0;
  double kinetic_energy = 0.0;  // eq. 4.15
  Vec<D> momentum = Vec<D>::Zero();
  double mean_speed = 0.0;  // mass-weighted mean speed, eq. 5.12
  double max_speed = 0.0;
  long yielding = 0;  // points whose last stress update was plastic
};

// Outcome of one step. A step that fails names the first offending particle.
struct StepStatus {
  bool ok = true;
  long particle = -1;
  std::string reason;
};

// Nodal fields of the last grid smoothing (Thesis eq. 4.18), flat-indexed like the grid, for
// the grid output file: m_i, v_i = sum N_ip m_p v_p / m_i and sigma_i. Zero pages where no point
// reaches (core/huge_pages.hpp); in a distributed run each process forms them over its own box,
// and the first process, which writes the grid's file, has them on the whole grid.
template <int D>
struct NodalSmoothing {
  GridArray<double> mass;
  GridArray<Vec<D>> velocity;
  GridArray<Sym3> stress;
};

template <int D>
struct MpmState {
  // The grid's cubic B-spline degrees of freedom sit at the Greville abscissae (core/grid.hpp):
  // the state sets grid.bspline_dofs from the kernel. Materials are prepared as the stage's.
  MpmState(Particles<D>& points, GridGeometry<D> grid, Interpolation interpolation, int quadrature_points,
           std::vector<Material> materials, int threads);

  Particles<D>& points;
  GridGeometry<D> grid;
  Interpolation interpolation;
  int quadrature_points;
  std::vector<Material> materials;  // the current stage's, prepared
  SolverClock clock;
  int threads;
  // The processes the points are split among (parallel/processes.hpp): this one's share is
  // `points`; sums over the points are every process's.
  Processes processes;
  NodalSmoothing<D> smoothing;  // of the last smoothed_stress() call

  // The gravity acting now: ramped from the stage's start (Thesis eq. 4.13).
  Vec<D> gravity(const Vec<D>& full) const {
    return gravity_at<D>(full, clock.gravity_ramp_time, clock.time - clock.ramp_start);
  }
};

// Sums over the points: mass, kinetic energy (eq. 4.15), momentum, mean (eq. 5.12) and largest
// speed, yielding points.
template <int D>
ParticleTotals<D> particle_totals(const Particles<D>& points, int threads, const Processes& processes = {});

// A new stage at the current time: its materials (prepared), the gravity ramp measured from now
// (eq. 4.13), displacements and energy totals measured from here. Plastic state that a stage held
// elastic did not track: the volume strain restarts at ln det F and no point yields yet.
template <int D>
void begin_stage(MpmState<D>& state, std::vector<Material> materials, double gravity_ramp_time);

// A checkpoint's (or the previous integrator's) clock with the current stage's materials.
template <int D>
void restore(MpmState<D>& state, const SolverClock& clock, std::vector<Material> materials);

// Grid-smoothed point stresses (Thesis eq. 4.18-4.19): sigma_i = sum sigma_p N_ip m_p / m_i at
// the nodes (kept in state.smoothing with m_i and v_i), then sigma_p = sum sigma_i N_ip. `out` is
// resized to the point count.
template <int D>
void smoothed_stress(MpmState<D>& state, std::vector<Sym3>& out);

}  // namespace skred
