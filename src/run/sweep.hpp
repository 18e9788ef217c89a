// Parameter sweeps: one scenario run for each value of one parameter, or for each point of a
// grid of values of several (e.g. the friction angle of Thesis fig. 5.14-5.16 against the
// cohesion), one table row per run with the last stage's slide measures.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "io/summary_writer.hpp"

namespace skred {

struct SweepAxis {
  std::string key;             // key path, e.g. "material[sand].friction"
  std::vector<double> values;  // in this order
};

struct SweepOptions {
  // One run per combination of values (the grid), the first axis varying slowest.
  std::vector<SweepAxis> axes;
  int threads = 1;
  bool progress = true;
};

struct SweepRow {
  std::vector<double> values;  // one per axis
  std::string status;          // "completed", "unstable" or "left_grid"
  std::string folder;          // run folder, relative to the sweep folder
  long steps = 0;
  double simulated_time = 0.0, wall_seconds = 0.0;
  StageMeasures last;              // the last stage's slide measures (stop_time unset: NaN in the table)
  double limit_equilibrium = NAN;  // Bishop's F (RunResult::limit_equilibrium)
};

// "KEY=V1,V2,..." where each item is a number or a range FROM:TO:STEP (TO included, values
// rounded to 12 significant digits so that 0.1:0.3:0.1 gives 0.3, not 0.30000000000000004).
// Throws std::invalid_argument with a message quoting the bad part.
SweepAxis parse_sweep_axis(const std::string& set);

// The grid of runs: every combination of the axes' values, the first axis slowest. Throws
// std::invalid_argument if there is no axis, a key repeats or the grid exceeds 10,000 runs.
std::vector<std::vector<double>> sweep_grid(const std::vector<SweepAxis>& axes);

// Runs the scenario once per grid point into OUTDIR/run_K/ and writes OUTDIR/sweep.csv
// (rewritten atomically after every run, so it is always complete). Every grid point is
// validated before the first run starts; a bad key or value throws ScenarioError naming the
// file and key.
std::vector<SweepRow> run_sweep(const std::string& scenario_file, const std::filesystem::path& outdir,
                                const SweepOptions& opt);

// The text of sweep.csv: a header (the swept keys, then status, folder, steps,
// simulated_time, wall_seconds, stage, ended_by and every slide measure of StageMeasures:
// runout ... plastic_points, with runout_z_min/max when a row has them: a 3D run) and one
// row per run. Real numbers have 12 significant digits (printf's %.12g: 0.05, not the
// 0.05000000000000004 of a sum of time steps); "nan" when unset (pandas and numpy read it as
// NaN).
std::string sweep_table(const std::vector<SweepAxis>& axes, const std::vector<SweepRow>& rows);

}  // namespace skred
