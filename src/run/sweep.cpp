#include "run/sweep.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <set>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "run/simulation.hpp"
#include "run/table_text.hpp"
#include "scenario/scenario.hpp"

namespace skred {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxRuns = 10000;

double parse_number(const std::string& x) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(x, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (x.empty() || used != x.size() || !std::isfinite(v))
    throw std::invalid_argument("'" + x + "' is not a number");
  return v;
}

// A value of a range FROM + k STEP without the rounding noise of the sum: the nearest double
// to its 12-significant-digit decimal (the inputs, as typed, have fewer).
double clean(double v) { return std::stod(fmt::format("{:.12g}", v)); }

std::string num(double v) { return table_number(v); }

bool is_three_d(const std::vector<SweepRow>& rows) {
  for (const SweepRow& r : rows)
    if (!std::isnan(r.last.runout_z_min) || !std::isnan(r.last.runout_z_max)) return true;
  return false;
}

}  // namespace

SweepAxis parse_sweep_axis(const std::string& set) {
  SweepAxis a;
  const auto eq = set.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == set.size())
    throw std::invalid_argument("expected KEY=V1,V2,... or KEY=FROM:TO:STEP, got '" + set + "'");
  a.key = set.substr(0, eq);
  std::stringstream items(set.substr(eq + 1));
  for (std::string item; std::getline(items, item, ',');) {
    std::vector<double> parts;
    std::stringstream ps(item);
    for (std::string x; std::getline(ps, x, ':');) parts.push_back(parse_number(x));
    if (!item.empty() && item.back() == ':') parts.clear();  // "1:2:" has no step
    if (parts.size() == 1) {
      a.values.push_back(parts[0]);
    } else if (parts.size() == 3 && parts[2] > 0 && parts[1] >= parts[0]) {
      const double n = std::floor((parts[1] - parts[0]) / parts[2] + 1e-9);
      if (n >= 1000) throw std::invalid_argument("a range may give at most 1000 values ('" + item + "')");
      for (long k = 0; k <= static_cast<long>(n); ++k) a.values.push_back(clean(parts[0] + k * parts[2]));
    } else {
      throw std::invalid_argument("'" + item +
                                  "' must be a number or FROM:TO:STEP with STEP > 0 and TO >= FROM");
    }
  }
  if (a.values.empty()) throw std::invalid_argument("no value in '" + set + "'");
  return a;
}

std::vector<std::vector<double>> sweep_grid(const std::vector<SweepAxis>& axes) {
  if (axes.empty()) throw std::invalid_argument("nothing to sweep: give --set KEY=VALUES");
  std::set<std::string> keys;
  std::size_t runs = 1;
  for (const SweepAxis& a : axes) {
    if (!keys.insert(a.key).second) throw std::invalid_argument("key '" + a.key + "' is swept twice");
    runs *= a.values.size();
    if (runs > kMaxRuns)
      throw std::invalid_argument(fmt::format("a sweep may have at most {} runs", kMaxRuns));
  }
  std::vector<std::vector<double>> grid(1);
  for (const SweepAxis& a : axes) {  // the last axis ends up varying fastest
    std::vector<std::vector<double>> next;
    for (const auto& point : grid)
      for (double v : a.values) {
        next.push_back(point);
        next.back().push_back(v);
      }
    grid = std::move(next);
  }
  return grid;
}

std::string sweep_table(const std::vector<SweepAxis>& axes, const std::vector<SweepRow>& rows) {
  const bool three_d = is_three_d(rows);
  std::string text;
  for (const SweepAxis& a : axes) text += table_text(a.key) + ",";
  text += "status,folder,steps,simulated_time,wall_seconds,stage,ended_by,runout,runout_x_min,runout_x_max,";
  if (three_d) text += "runout_z_min,runout_z_max,";
  text +=
      "max_displacement,height_start,height_end,peak_mean_speed,peak_time,final_mean_speed,stop_time,"
      "gravity_work,kinetic_energy_change,strain_energy,plastic_dissipation,plastic_volume,plastic_points,"
      "limit_equilibrium\n";
  auto out = std::back_inserter(text);
  for (const SweepRow& r : rows) {
    for (double v : r.values) fmt::format_to(out, "{},", num(v));
    const StageMeasures& m = r.last;
    fmt::format_to(out, "{},{},{},{},{},{},{},{},{},{},", r.status, r.folder, r.steps, num(r.simulated_time),
                   num(r.wall_seconds), table_text(m.name), m.ended_by, num(m.runout), num(m.runout_x_min),
                   num(m.runout_x_max));
    if (three_d) fmt::format_to(out, "{},{},", num(m.runout_z_min), num(m.runout_z_max));
    fmt::format_to(out, "{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", num(m.max_displacement),
                   num(m.height_start), num(m.height_end), num(m.peak_mean_speed), num(m.peak_time),
                   num(m.final_mean_speed), num(m.stop_time.value_or(NAN)), num(m.gravity_work),
                   num(m.kinetic_energy_change), num(m.strain_energy), num(m.plastic_dissipation),
                   num(m.plastic_volume), m.plastic_points, num(r.limit_equilibrium));
  }
  return text;
}

std::vector<SweepRow> run_sweep(const std::string& scenario_file, const fs::path& outdir,
                                const SweepOptions& opt) {
  const std::string text = read_scenario_text(scenario_file);
  const auto grid = sweep_grid(opt.axes);
  std::vector<AnyScenario> scenarios;  // validate every grid point before running anything
  for (const auto& point : grid) {
    std::vector<std::pair<std::string, double>> overrides;
    for (std::size_t k = 0; k < opt.axes.size(); ++k) overrides.emplace_back(opt.axes[k].key, point[k]);
    scenarios.push_back(parse_any_scenario(text, scenario_file, overrides));
  }
  fs::create_directories(outdir);
  std::vector<SweepRow> rows;
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    SweepRow row;
    row.values = grid[i];
    row.folder = fmt::format("run_{:03}", i);
    if (opt.progress) {
      std::string what;
      for (std::size_t k = 0; k < opt.axes.size(); ++k)
        what += fmt::format("{}{} = {}", k ? ", " : "", opt.axes[k].key, num(row.values[k]));
      fmt::print(stderr, "sweep {}/{}: {}\n", i + 1, scenarios.size(), what);
    }
    RunOptions ro;
    ro.threads = opt.threads;
    ro.progress = opt.progress;
    const RunResult res = run_simulation(scenarios[i], outdir / row.folder, ro);
    row.status = run_status(res);
    row.steps = res.steps;
    row.simulated_time = res.simulated_time;
    row.wall_seconds = res.wall_seconds;
    if (!res.stages.empty()) row.last = res.stages.back();
    row.limit_equilibrium = res.limit_equilibrium;
    rows.push_back(row);
    write_file_atomically(outdir / "sweep.csv", [&](std::ostream& os) { os << sweep_table(opt.axes, rows); });
  }
  return rows;
}

}  // namespace skred
