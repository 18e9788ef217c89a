// Runs a scenario from start to end: builds the material points, steps the solver and
// writes the result files (particle frames, series.csv, summary.json).
#pragma once
#include <filesystem>
#include <functional>
#include <string>

#include "implicit/implicit_solver.hpp"
#include "io/summary_writer.hpp"
#include "parallel/processes.hpp"
#include "scenario/estimate.hpp"
#include "scenario/scenario.hpp"
#include "solver/explicit_solver.hpp"
#include "solver/integrator.hpp"

namespace skred {

struct RunOptions {
  int threads = 1;
  bool progress = true;          // progress line on stderr
  long sort_every = kSortEvery;  // 0: never sort
  // Checkpoints (run/checkpointing.hpp): OUTDIR/checkpoint.skc every N steps and at the end
  // (0: none, except on a signal); continue from `restart` when set; on SIGINT/SIGTERM write a
  // checkpoint and stop with status "interrupted" when handle_signals.
  long checkpoint_every = 0;
  std::filesystem::path restart;
  bool handle_signals = false;
  long stop_at_step = -1;  // stop as if interrupted after this step (tests)
  // Ends the run, completed, once a point of stage `stop_stage` has moved more than
  // `stop_moved` times the material's height at the stage start (checked at every series row;
  // the stage ends_by "moved"): a strength-reduction run that has failed
  // (run/strength_reduction.hpp). -1: never.
  int stop_stage = -1;
  double stop_moved = 0.0;
  // Called before every step; may change the points (their number too) and then returns true
  // (tests of the point lifecycle, adaptive refinement).
  std::function<bool(Particles<2>&, const ExplicitSolver<2>&)> edit_points;
  // The processes the run is split among (parallel/processes.hpp; docs/method.md, "Runs over
  // several processes"): each steps its share of the points, the first writes series.csv,
  // summary.json, the indexes and the grid files, each its piece of every particle frame and
  // of every checkpoint. Explicit stages only.
  Processes processes;
};

struct RunResult {
  bool completed = false;
  bool interrupted = false;  // stopped by a signal (or stop_at_step) after a checkpoint
  bool left_grid = false;    // stopped because a sound point left the grid (not completed)
  std::string message;
  long steps = 0;
  double simulated_time = 0.0;
  long particles = 0;
  double wall_seconds = 0.0;
  double particle_updates_per_second = 0.0;
  std::vector<StageMeasures> stages;  // slide measures per stage run
  double limit_equilibrium = NAN;     // Bishop's F of the bodies at the start (2D slopes)
};

template <int D>
SolverSettings<D> solver_settings(const ScenarioOf<D>& s);

// What the implicit integrator takes from a scenario (grid, kernel, gravity, walls, geometry,
// pressures), and the step of a stage: the explicit time step, an implicit dynamic stage's
// time step, or a quasi-static stage's duration over its load steps.
template <int D>
ImplicitModel<D> implicit_model(const ScenarioOf<D>& s);
template <int D>
double stage_time_step(const ScenarioOf<D>& s, const Stage& st);

// The background grid of a scenario (origin, cell size, cells per axis).
template <int D>
GridGeometry<D> scenario_grid(const ScenarioOf<D>& s);

// Runs a 2D or 3D scenario (the driver is the same template; 3D adds momentum_z to
// series.csv and the runout along z to summary.json).
template <int D>
RunResult run_simulation(const ScenarioOf<D>& s, const std::filesystem::path& outdir, const RunOptions& opt);
RunResult run_simulation(const AnyScenario& s, const std::filesystem::path& outdir, const RunOptions& opt);

}  // namespace skred
