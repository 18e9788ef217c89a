// A scenario given as text, run to its end in a temporary folder (removed afterwards): for the
// tests that run variants of the examples and read their results and energies.
#pragma once
#include <filesystem>
#include <map>
#include <string>

#include "run/simulation.hpp"
#include "scenario/scenario.hpp"
#include "support.hpp"
#include "temp_dir.hpp"

namespace skred::test {

struct TextRun {
  RunResult result;
  std::map<std::string, double> row;  // series.csv's last row
  // The energy balance: total_energy (kinetic + strain + every dissipation - gravity work)
  // against the gravity work.
  double balance() const { return row.at("total_energy") / row.at("gravity_work"); }
};

// `name` is the source named in parse errors.
inline TextRun run_text(const std::string& text, int threads, const std::string& name = "column.toml") {
  const std::filesystem::path out = fresh_temp_dir();
  RunOptions opt;
  opt.progress = false;
  opt.threads = threads;
  TextRun r{run_simulation(parse_scenario(text, name), out, opt), {}};
  r.row = last_series_row(out / "series.csv");
  std::filesystem::remove_all(out);
  return r;
}

}  // namespace skred::test
