// Runs a scenario from start to end: builds the material points, steps the solver and
// writes the result files (particle frames, series.csv, summary.json).
#pragma once
#include <filesystem>
#include <string>

#include "io/summary_writer.hpp"
#include "scenario/scenario.hpp"
#include "solver/explicit_solver.hpp"

namespace skred {

struct RunOptions {
  int threads = 1;
  bool progress = true;  // progress line on stderr
};

struct RunResult {
  bool completed = false;
  std::string message;
  long steps = 0;
  double simulated_time = 0.0;
  long particles = 0;
  double wall_seconds = 0.0;
  double particle_updates_per_second = 0.0;
  std::vector<StageMeasures> stages;  // slide measures per stage run
};

// The time step of a scenario: the fixed one, or cfl * h / (fastest P-wave speed +
// fastest initial particle speed).
double scenario_time_step(const Scenario& s);

SolverSettings<2> solver_settings(const Scenario& s);

// The background grid of a scenario (origin, cell size, cells per axis).
GridGeometry<2> scenario_grid(const Scenario& s);

RunResult run_simulation(const Scenario& s, const std::filesystem::path& outdir, const RunOptions& opt);

}  // namespace skred
