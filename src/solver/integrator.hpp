// What the run driver (src/run) asks of a time integrator, so that the stage loop, sampling,
// frames, checkpoints and `skred check` serve the explicit solver (solver/explicit_solver.hpp,
// wrapped by solver/explicit_integrator.hpp) and the implicit one (src/implicit) alike. Both
// advance the same points (core/particles.hpp); a run may change integrator between stages,
// handing the clock over with clock() and restore().
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "core/grid.hpp"
#include "core/particles.hpp"
#include "material/material.hpp"
#include "solver/explicit_solver.hpp"
#include "solver/implicit_settings.hpp"

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
  // Advances by one step (the stage's time or load step; an implicit step may be cut).
  virtual StepStatus step() = 0;
  // The points changed between steps (their positions, number, state): map afresh.
  virtual void particles_changed() = 0;
  virtual double time() const = 0;
  virtual long steps() const = 0;
  // The step the integrator takes next [s].
  virtual double dt() const = 0;
  virtual const EnergyTotals& energy() const = 0;
  virtual ParticleTotals<D> totals() const = 0;
  virtual double material_mean_speed() = 0;
  virtual const GridGeometry<D>& grid() const = 0;
  virtual int threads() const = 0;
  virtual bool sort_by_nearest_node() const = 0;
  virtual bool contact_on() const = 0;
  // A new stage at the current time (ExplicitSolver::begin_stage); the implicit integrator also
  // takes the stage's settings and end time (set_stage) first.
  virtual void begin_stage(std::vector<Material> materials, double gravity_ramp_time) = 0;
  virtual void set_local_damping(double alpha) = 0;
  virtual const std::vector<Material>& materials() const = 0;
  // Grid-smoothed stresses (Thesis eq. 4.18-4.19) and the nodal fields of that call.
  virtual void smoothed_stress(std::vector<Sym3>& out) = 0;
  virtual const std::vector<double>& node_mass() const = 0;
  virtual const std::vector<Vec<D>>& node_velocity() const = 0;
  virtual const std::vector<Sym3>& node_stress() const = 0;
  // Checkpoint and restart, and the hand-over between integrators.
  virtual SolverClock clock() const = 0;
  virtual void restore(const SolverClock& c, std::vector<Material> materials) = 0;
  // (phase, seconds) of every phase that ran, in step order (summary.json).
  virtual std::vector<std::pair<std::string, double>> phase_seconds() const = 0;
  virtual StepReport last_step() const { return {}; }
};

}  // namespace skred
