#include "run/sweep.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iterator>

#include "io/atomic_file.hpp"
#include "run/simulation.hpp"
#include "scenario/scenario.hpp"

namespace skred {

namespace fs = std::filesystem;

std::string sweep_header(const std::string& key) {
  return fmt::format(
      "{},status,folder,steps,simulated_time,wall_seconds,runout,runout_x_min,"
      "runout_x_max,height_end,peak_mean_speed,final_mean_speed,stop_time,"
      "gravity_work,plastic_dissipation,plastic_volume\n",
      key);
}

namespace {

void write_table(const fs::path& file, const std::string& key, const std::vector<SweepRow>& rows) {
  std::string text = sweep_header(key);
  for (const SweepRow& r : rows)
    fmt::format_to(std::back_inserter(text), "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", r.value,
                   r.status, r.folder, r.steps, r.simulated_time, r.wall_seconds, r.runout, r.runout_x_min,
                   r.runout_x_max, r.height_end, r.peak_mean_speed, r.final_mean_speed, r.stop_time,
                   r.gravity_work, r.plastic_dissipation, r.plastic_volume);
  write_file_atomically(file, [&](std::ostream& os) { os << text; });
}

}  // namespace

std::vector<SweepRow> run_sweep(const std::string& scenario_file, const fs::path& outdir,
                                const SweepOptions& opt) {
  const std::string text = read_scenario_text(scenario_file);
  std::vector<AnyScenario> scenarios;  // validate every value before running anything
  for (double v : opt.values) scenarios.push_back(parse_any_scenario(text, scenario_file, {{opt.key, v}}));
  fs::create_directories(outdir);
  std::vector<SweepRow> rows;
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    SweepRow row;
    row.value = opt.values[i];
    row.folder = fmt::format("run_{:03}", i);
    if (opt.progress)
      fmt::print(stderr, "sweep {}/{}: {} = {}\n", i + 1, scenarios.size(), opt.key, row.value);
    RunOptions ro;
    ro.threads = opt.threads;
    ro.progress = opt.progress;
    const RunResult res = run_simulation(scenarios[i], outdir / row.folder, ro);
    row.status = res.completed ? "completed" : res.left_grid ? "left_grid" : "unstable";
    row.steps = res.steps;
    row.simulated_time = res.simulated_time;
    row.wall_seconds = res.wall_seconds;
    if (!res.stages.empty()) {
      const StageMeasures& m = res.stages.back();
      row.runout = m.runout;
      row.runout_x_min = m.runout_x_min;
      row.runout_x_max = m.runout_x_max;
      row.height_end = m.height_end;
      row.peak_mean_speed = m.peak_mean_speed;
      row.final_mean_speed = m.final_mean_speed;
      row.stop_time = m.stop_time.value_or(NAN);
      row.gravity_work = m.gravity_work;
      row.plastic_dissipation = m.plastic_dissipation;
      row.plastic_volume = m.plastic_volume;
    }
    rows.push_back(row);
    write_table(outdir / "sweep.csv", opt.key, rows);
  }
  return rows;
}

}  // namespace skred
