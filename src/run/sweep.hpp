// Parameter sweeps: one scenario run for each value of one parameter (e.g. the friction
// angle of Thesis fig. 5.14-5.16), one table row per run with the last stage's slide measures.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace skred {

struct SweepOptions {
  std::string key;             // key path, e.g. "material[sand].friction"
  std::vector<double> values;  // one run per value, in this order
  int threads = 1;
  bool progress = true;
};

struct SweepRow {
  double value = 0.0;
  std::string status;  // "completed", "unstable" or "error: ..."
  std::string folder;  // run folder, relative to the sweep folder
  long steps = 0;
  double simulated_time = 0.0, wall_seconds = 0.0;
  double runout = 0.0, runout_x_min = 0.0, runout_x_max = 0.0, height_end = 0.0;
  double peak_mean_speed = 0.0, final_mean_speed = 0.0, stop_time = 0.0;  // NaN if none
  double gravity_work = 0.0, plastic_dissipation = 0.0, plastic_volume = 0.0;
};

// Runs the scenario once per value into OUTDIR/run_K/ and writes OUTDIR/sweep.csv (rewritten
// atomically after every run, so it is always complete). Every value is validated before the
// first run starts; a bad key or value throws ScenarioError naming the file and key.
std::vector<SweepRow> run_sweep(const std::string& scenario_file, const std::filesystem::path& outdir,
                                const SweepOptions& opt);

// Column names of sweep.csv (the first is the swept key itself).
std::string sweep_header(const std::string& key);

}  // namespace skred
