// What the run driver (src/run) asks of a time integrator, so that the stage loop, sampling,
// frames, checkpoints and `skred check` serve the explicit solver (solver/explicit_solver.hpp,
// wrapped by solver/explicit_integrator.hpp) and the implicit one (src/implicit) alike. Both
// advance the same points (core/particles.hpp); a run may change integrator between stages,
// handing the clock over with clock() and restore().
#pragma once
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/grid.hpp"
#include "core/particles.hpp"
#include "material/material.hpp"
#include "solver/explicit_solver.hpp"
#include "solver/implicit_settings.hpp"
#include "solver/mpm_state.hpp"

namespace skred {

// How the last step went, for the progress line and series.csv (implicit steps: the Newton
// iterations and the final out-of-balance force, relative to the step's force scale).
struct StepReport {
  int iterations = 0;
  double residual = 0.0;
  int cuts = 0;  // times the step was halved before it converged
};

template <int D>
class Integrator {
 public:
  virtual ~Integrator() = default;

  virtual IntegratorKind kind() const = 0;
  // The points, grid, materials and clock the integrator advances (mpm_state.hpp): what the run
  // driver reads between steps, the same for both integrators.
  virtual const MpmState<D>& state() const = 0;
  // Advances by one step (the stage's time or load step; an implicit step may be cut).
  virtual StepStatus step() = 0;
  // The points changed between steps (their positions, number, state): map afresh.
  virtual void particles_changed() = 0;
  // The step the integrator takes next [s].
  virtual double dt() const = 0;
  // The particle totals (particle_totals; the explicit solver adds APIC's affine kinetic energy).
  virtual ParticleTotals<D> totals() const = 0;
  virtual double material_mean_speed() = 0;
  virtual bool sort_by_nearest_node() const = 0;
  virtual bool contact_on() const = 0;
  // A new stage at the current time (begin_stage, mpm_state.hpp); the implicit integrator also
  // takes the stage's settings and end time (set_stage) first.
  virtual void begin_stage(std::vector<Material> materials, double gravity_ramp_time) = 0;
  virtual void set_local_damping(double alpha) = 0;
  // Grid-smoothed stresses (Thesis eq. 4.18-4.19; smoothed_stress, mpm_state.hpp).
  virtual void smoothed_stress(std::vector<Sym3>& out) = 0;
  // Checkpoint and restart, and the hand-over between integrators.
  virtual void restore(const SolverClock& c, std::vector<Material> materials) = 0;
  // (phase, seconds) of every phase that ran, in step order (summary.json).
  virtual std::vector<std::pair<std::string, double>> phase_seconds() const = 0;
  virtual StepReport last_step() const { return {}; }
  // Per grid node, the stiffness magnitude K_mag and the internal force's |F_int| of the last
  // step (Acosta eq. 25-26; the implicit integrator); false when the integrator has none.
  // Across processes (collective) the first process has every node's, the others their box's.
  virtual bool node_magnitudes(std::vector<double>& k_mag, std::vector<double>& f_mag) const {
    (void)k_mag;
    (void)f_mag;
    return false;
  }

  // Read from the shared state.
  double time() const { return state().clock.time; }
  long steps() const { return state().clock.steps; }
  const EnergyTotals& energy() const { return state().clock.energy; }
  const SolverClock& clock() const { return state().clock; }
  const GridGeometry<D>& grid() const { return state().grid; }
  int threads() const { return state().threads; }
  const std::vector<Material>& materials() const { return state().materials; }
  // The nodal fields of the last smoothed_stress() call.
  std::span<const double> node_mass() const { return state().smoothing.mass; }
  std::span<const Vec<D>> node_velocity() const { return state().smoothing.velocity; }
  std::span<const Sym3> node_stress() const { return state().smoothing.stress; }
};

}  // namespace skred
