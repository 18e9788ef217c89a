// skred command line: run a scenario, check a scenario, measure throughput, or draw results.
#include <fmt/core.h>
#include <omp.h>

#include <CLI/CLI.hpp>
#include <filesystem>

#include "app/post_cli.hpp"
#include "run/bench.hpp"
#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "scenario/scenario.hpp"

namespace {

int cmd_run(const std::string& file, const std::string& outdir, int threads) {
  const skred::Scenario s = skred::load_scenario(file);
  skred::RunOptions opt;
  opt.threads = threads > 0 ? threads : omp_get_max_threads();
  const auto res = skred::run_simulation(s, outdir, opt);
  if (!res.completed) {
    fmt::print(stderr, "skred: {}\n", res.message);
    return 2;
  }
  fmt::print("completed {} steps ({:.4g} s simulated) with {} particles in {:.2f} s wall, "
             "{:.2f} M particle-updates/s; results in {}\n",
             res.steps, res.simulated_time, res.particles, res.wall_seconds,
             res.particle_updates_per_second / 1e6, outdir);
  return 0;
}

int cmd_check(const std::string& file) {
  const skred::Scenario s = skred::load_scenario(file);
  const auto particles = skred::build_particles(s);
  fmt::print("{}\nparticles: {}\ntime step: {:.6g} s ({} steps)\nscenario is valid\n",
             skred::describe(s), particles.size(), skred::scenario_time_step(s),
             static_cast<long>(std::ceil(s.end_time / skred::scenario_time_step(s) - 1e-9)));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"skred: material point method for large-deformation geomechanics"};
  app.require_subcommand(1);

  std::string scenario, outdir;
  int threads = 0;
  auto* run = app.add_subcommand("run", "Run a scenario and write results");
  run->add_option("scenario", scenario, "Scenario file (TOML)")->required()->check(CLI::ExistingFile);
  run->add_option("-o,--output", outdir, "Output folder")->required();
  run->add_option("--threads", threads, "OpenMP threads (default: all cores)")->check(CLI::Range(1, 1024));

  auto* check = app.add_subcommand("check", "Validate a scenario without running it");
  check->add_option("scenario", scenario, "Scenario file (TOML)")->required()->check(CLI::ExistingFile);

  skred::BenchOptions bo;
  std::string interp = "gimp", scheme = "averaged";
  auto* bench = app.add_subcommand("bench", "Measure particle-updates per second");
  bench->add_option("--particles", bo.particles, "Approximate number of particles")->check(CLI::Range(100L, 100000000L));
  bench->add_option("--steps", bo.steps, "Timed steps per repeat")->check(CLI::Range(1, 1000000));
  bench->add_option("--repeats", bo.repeats, "Repeats (the median is reported)")->check(CLI::Range(1, 1000));
  bench->add_option("--threads", threads, "OpenMP threads (default: all cores)")->check(CLI::Range(1, 1024));
  bench->add_option("--interpolation", interp, "linear | gimp | gimp-quadrature | bspline")
      ->check(CLI::IsMember({"linear", "gimp", "gimp-quadrature", "bspline"}));
  bench->add_option("--quadrature-points", bo.quadrature_points, "1, 2 or 3")->check(CLI::Range(1, 3));
  bench->add_option("--scheme", scheme, "usf | usl | averaged")->check(CLI::IsMember({"usf", "usl", "averaged"}));

  skred::PostCommands post(app);  // render, report

  CLI11_PARSE(app, argc, argv);
  if (post.chosen()) return post.run();
  try {
    if (*run) return cmd_run(scenario, outdir, threads);
    if (*check) return cmd_check(scenario);
    if (*bench) {
      bo.threads = threads > 0 ? threads : omp_get_max_threads();
      bo.interpolation = interp == "linear" ? skred::Interpolation::Linear
                         : interp == "gimp" ? skred::Interpolation::Gimp
                         : interp == "bspline" ? skred::Interpolation::Bspline
                                               : skred::Interpolation::GimpQuadrature;
      bo.scheme = scheme == "usf" ? skred::StressScheme::USF
                  : scheme == "usl" ? skred::StressScheme::USL
                                    : skred::StressScheme::Averaged;
      const auto r = skred::run_bench(bo);
      fmt::print("bench: {} particles, {} grid nodes, {} steps x {} repeats, {} thread(s), {} / {}\n",
                 r.particles, r.nodes, bo.steps, bo.repeats, bo.threads, interp, scheme);
      for (double u : r.updates_per_second) fmt::print("  run: {:.3f} M particle-updates/s\n", u / 1e6);
      fmt::print("median: {:.3f} M particle-updates/s ({:.3f} M per thread)\n", r.median / 1e6,
                 r.median / 1e6 / bo.threads);
      fmt::print("peak memory: {:.1f} MB, {:.0f} bytes per particle\n", r.peak_rss_bytes / 1e6,
                 r.peak_rss_bytes / r.particles);
    }
  } catch (const skred::ScenarioError& e) {
    fmt::print(stderr, "skred: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "skred: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
