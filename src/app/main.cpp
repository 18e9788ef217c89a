// skred command line: run a scenario, check a scenario, measure throughput, or draw results.
#include <fmt/core.h>
#include <malloc.h>
#include <omp.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <exception>
#include <filesystem>
#include <new>
#include <sstream>
#include <stdexcept>
#include <variant>
#include <vector>

#include "app/exit_codes.hpp"
#include "app/launched_processes.hpp"
#include "app/omp_wait.hpp"
#include "app/post_cli.hpp"
#include "app/scenario_cli.hpp"
#include "io/checkpoint.hpp"
#include "parallel/processes.hpp"
#include "run/bench.hpp"
#include "run/checkpointing.hpp"
#include "run/extrapolation_text.hpp"
#include "run/output_folder.hpp"
#include "run/refine.hpp"
#include "run/simulation.hpp"
#include "run/slope_stability.hpp"
#include "run/strength_reduction.hpp"
#include "run/sweep.hpp"
#include "run/version.hpp"
#include "scenario/build.hpp"
#include "scenario/estimate.hpp"
#include "scenario/scenario.hpp"

namespace {

namespace code = skred::exit_code;

std::string memory_text(double bytes) { return fmt::format("{:.3g} GB", bytes / 1e9); }

// A new run (not a continuation) refuses an OUTDIR holding an earlier run unless --overwrite,
// which removes that run's files first (run/output_folder.hpp).
// Exits: completed, unstable (or a point left the grid), interrupted (SIGINT/SIGTERM; a
// checkpoint was written, continue with `skred resume OUTDIR`); see app/exit_codes.hpp.
int cmd_run(const std::string& file, const std::string& outdir, int threads, skred::RunOptions opt,
            bool overwrite) {
  skred::watch_stop_signals();
  const skred::AnyScenario s = skred::load_any_scenario(file);
  const skred::Processes& procs = opt.processes;
  if (opt.restart.empty()) {  // by the first process; the others wait to hear that it could
    std::exception_ptr failed;
    if (procs.rank() == 0) try {
        skred::prepare_output_folder(outdir, overwrite, file);
      } catch (...) {
        failed = std::current_exception();
      }
    if (procs.any(failed != nullptr)) {
      if (failed) std::rethrow_exception(failed);
      return code::kError;
    }
  }
  opt.threads = threads > 0 ? threads : omp_get_max_threads();
  opt.handle_signals = true;
  const auto res = skred::run_simulation(s, outdir, opt);
  if (procs.rank() != 0)  // (the first process reports)
    return res.interrupted ? code::kInterrupted : res.completed ? code::kSuccess : code::kUnstable;
  if (res.interrupted) {
    fmt::print(stderr, "skred: {}\n", res.message);
    return code::kInterrupted;
  }
  if (!res.completed) {
    fmt::print(stderr, "skred: {}\n", res.message);
    return code::kUnstable;
  }
  fmt::print(
      "completed {} steps ({:.4g} s simulated) with {} particles in {:.2f} s wall, "
      "{:.2f} M particle-updates/s; results in {}\n",
      res.steps, res.simulated_time, res.particles, res.wall_seconds, res.particle_updates_per_second / 1e6,
      outdir);
  return code::kSuccess;
}

// Draws a study's picture from its table (skred-post KIND OUTDIR): success, or the exit code
// when it could not be drawn (the table is complete either way).
int draw_study(const std::string& kind, const std::string& outdir, const std::filesystem::path& table) {
  const int drawn = skred::run_post({kind, outdir});
  if (drawn == code::kSuccess) return code::kSuccess;
  fmt::print(stderr, "skred: the {}'s picture was not drawn; {} is complete\n",
             kind == "sweep" ? "sweep" : "study", table.string());
  return drawn == code::kMissingPython ? code::kMissingPython : code::kError;
}

// One run per point of the grid of --set values; then sweep.csv's picture (pictures/sweep.png)
// is drawn by the Python post-processing. Exits: usage for a bad --set, unstable if a run
// was, missing Python if the picture could not be drawn (sweep.csv is written all the same).
int cmd_sweep(const std::string& file, const std::string& outdir, const std::vector<std::string>& sets,
              int threads, bool overwrite) {
  skred::SweepOptions o;
  try {
    for (const std::string& set : sets) o.axes.push_back(skred::parse_sweep_axis(set));
    skred::sweep_grid(o.axes);  // checks the keys and the number of runs
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--set", e.what());
  }
  skred::prepare_output_folder(outdir, overwrite, file);
  o.threads = threads > 0 ? threads : omp_get_max_threads();
  const auto rows = skred::run_sweep(file, outdir, o);
  for (const auto& a : o.axes) fmt::print("{:>14.14} ", a.key);
  fmt::print("{:>10} {:>10} {:>10} {:>12} {:>10}\n", "status", "runout", "height", "peak speed", "stop time");
  for (const auto& r : rows) {
    for (double v : r.values) fmt::print("{:>14.6g} ", v);
    fmt::print("{:>10} {:>10.4g} {:>10.4g} {:>12.4g} {:>10.4g}\n", r.status, r.last.runout, r.last.height_end,
               r.last.peak_mean_speed, r.last.stop_time.value_or(NAN));
  }
  const std::filesystem::path table = std::filesystem::path(outdir) / "sweep.csv";
  fmt::print("table: {}\n", table.string());
  if (const int drawn = draw_study("sweep", outdir, table); drawn != code::kSuccess) return drawn;
  for (const auto& r : rows)
    if (r.status != "completed") return code::kUnstable;
  return code::kSuccess;
}

// The scenario at h, h/2, ... per velocity transfer (run/refine.hpp); refine.csv, the verdict
// on the terminal and pictures/refine.png. Exits: usage for bad options, missing Python if the
// picture could not be drawn, unstable if a run was.
int cmd_refine(const std::string& file, const std::string& outdir, skred::RefineOptions o, int threads,
               bool overwrite) {
  try {
    skred::check_refine_options(o);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("refine", e.what());
  }
  skred::prepare_output_folder(outdir, overwrite, file);
  o.threads = threads > 0 ? threads : omp_get_max_threads();
  const auto rows = skred::run_refine(file, outdir, o);
  const std::filesystem::path table = std::filesystem::path(outdir) / "refine.csv";
  fmt::print("{}table: {}\n", skred::refine_verdict(rows), table.string());
  // How near the slope stands to failing says how much its runout can move with the cell
  // (docs/method.md, "Limit equilibrium").
  if (const skred::AnyScenario s = skred::load_any_scenario(file); std::holds_alternative<skred::Scenario>(s))
    if (const skred::SlopeStability le = skred::slope_stability(std::get<skred::Scenario>(s)); le.computed)
      fmt::print("{}", skred::slope_stability_line(le));
  if (const int drawn = draw_study("refine", outdir, table); drawn != code::kSuccess) return drawn;
  for (const auto& r : rows)
    if (r.status != "completed") return code::kUnstable;
  return code::kSuccess;
}

// The MPM's factor of safety by strength reduction (run/strength_reduction.hpp): fos.csv, the
// verdict on the terminal and pictures/fos.png. Exits: usage for bad options, missing Python if
// the picture could not be drawn, unstable if a run was.
int cmd_fos(const std::string& file, const std::string& outdir, skred::FosOptions o, int threads,
            bool overwrite) {
  try {
    skred::check_fos_options(o);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("fos", e.what());
  }
  skred::prepare_output_folder(outdir, overwrite, file);
  o.threads = threads > 0 ? threads : omp_get_max_threads();
  const skred::FosResult r = skred::run_strength_reduction(file, outdir, o);
  const std::filesystem::path table = std::filesystem::path(outdir) / "fos.csv";
  fmt::print("{}table: {}\n", skred::fos_verdict(r, o), table.string());
  if (const int drawn = draw_study("fos", outdir, table); drawn != code::kSuccess) return drawn;
  for (const auto& run : r.runs)
    if (run.status == "unstable") return code::kUnstable;
  return code::kSuccess;
}

}  // namespace

static int command(int argc, char** argv) {
  // Large arrays always come from the kernel and go back to it when freed. Left to itself,
  // glibc raises its mmap threshold after the first large free and serves later arrays from
  // the heap, which keeps freed memory resident (the bench's repeats then peak higher).
  mallopt(M_MMAP_THRESHOLD, 256 * 1024);
  CLI::App app{"skred: material point method for large-deformation geomechanics"};
  app.require_subcommand(1);
  app.set_version_flag(
      "--version",
      fmt::format("skred {} (commit {}){}", skred::version(), skred::git_commit(),
                  skred::built_with_mpi() ? ""
                                          : "\nbuilt without MPI and PETSc (cmake -DSKRED_MPI=OFF): runs in "
                                            "one process, explicit integrator only"));
  bool overwrite = false;

  std::string scenario, outdir;
  int threads = 0;
  auto* run = app.add_subcommand("run", "Run a scenario and write results");
  run->add_option("scenario", scenario, "Scenario file (TOML)")->required()->check(CLI::ExistingFile);
  run->add_option("-o,--output", outdir, "Output folder")->required();
  run->add_option("--threads", threads, "OpenMP threads (default: all cores)")->check(CLI::Range(1, 1024));
  skred::RunOptions ro;
  std::string restart;
  run->add_option("--checkpoint-every", ro.checkpoint_every,
                  "Write OUTDIR/checkpoint.skc every N steps and at the end")
      ->check(CLI::Range(1L, 1000000000L));
  run->add_option("--restart", restart,
                  "Continue from this checkpoint (of the same scenario): checkpoint.skc, or the "
                  "checkpoint.manifest of one in pieces")
      ->transform(CLI::Validator(
          [](std::string& path) -> std::string {  // (a checkpoint in pieces: its manifest stands for it)
            namespace fs = std::filesystem;
            const fs::path p(path), dir = p.parent_path();
            if (p.filename() == skred::checkpoint_manifest(dir).filename())
              path = skred::checkpoint_file(dir).string();
            if (fs::is_regular_file(path) ||
                (fs::path(path).filename() == skred::checkpoint_file(dir).filename() &&
                 fs::is_regular_file(skred::checkpoint_manifest(dir))))
              return {};
            return "File does not exist: " + p.string();
          },
          "FILE"));
  run->add_flag("--overwrite", overwrite, "Replace an earlier run in OUTDIR (removes its files first)");

  auto* resume = app.add_subcommand("resume", "Continue an interrupted run from OUTDIR/checkpoint.skc");
  resume->add_option("outdir", outdir, "Output folder of the run")->required()->check(CLI::ExistingDirectory);
  resume->add_option("--threads", threads, "OpenMP threads (default: all cores)")->check(CLI::Range(1, 1024));
  resume
      ->add_option("--checkpoint-every", ro.checkpoint_every,
                   "Checkpoint period in steps (default: that of the run)")
      ->check(CLI::Range(1L, 1000000000L));

  skred::ScenarioCommands scenario_commands(app);  // check, schema
  bool force = false;
  run->add_flag("--force", force, "Run a scenario that needs more memory than the machine has");

  std::vector<std::string> sets;
  auto* sweep = app.add_subcommand(
      "sweep", "Run a scenario once per value of a parameter, or per point of a grid of several");
  sweep->add_option("scenario", scenario, "Scenario file (TOML)")->required()->check(CLI::ExistingFile);
  sweep
      ->add_option(
          "--set", sets,
          "KEY=V1,V2,... or KEY=FROM:TO:STEP, e.g. material[sand].friction=15:30:3; repeat for a grid")
      ->required()
      ->expected(1)
      ->take_all();
  sweep
      ->add_option("-o,--output", outdir,
                   "Output folder (one sub-folder per run, sweep.csv, pictures/sweep.png)")
      ->required();
  sweep->add_option("--threads", threads, "OpenMP threads (default: all cores)")->check(CLI::Range(1, 1024));
  sweep->add_flag("--overwrite", overwrite, "Replace an earlier sweep in OUTDIR (removes its files first)");

  skred::RefineOptions rfo;
  auto* refine = app.add_subcommand(
      "refine", "Run a scenario at its cell size and at halves of it, and tell how far the runout moves");
  refine->add_option("scenario", scenario, "Scenario file (TOML)")->required()->check(CLI::ExistingFile);
  refine->add_option("-o,--output", outdir, "Output folder (one sub-folder per run, refine.csv)")->required();
  refine->add_option("--levels", rfo.levels, "Cell sizes h, h/2, ...: 2 to 5 (default 3)");
  refine
      ->add_option("--transfers", rfo.transfers,
                   "solver.velocity_transfer per series, e.g. auto,apic (default: the scenario's)")
      ->delimiter(',');
  refine->add_option("--threads", threads, "OpenMP threads (default: all cores)")->check(CLI::Range(1, 1024));
  refine->add_flag("--overwrite", overwrite, "Replace an earlier study in OUTDIR (removes its files first)");
  refine->add_flag("--force", force, "Run levels that need more memory than the machine has");

  skred::FosOptions fo;
  std::vector<double> fos_range;
  auto* fos = app.add_subcommand(
      "fos", "The MPM's factor of safety of a slope: bisect the strength reduction at which it fails");
  fos->add_option("scenario", scenario, "Scenario file (TOML)")->required()->check(CLI::ExistingFile);
  fos->add_option("-o,--output", outdir, "Output folder (one sub-folder per run, fos.csv)")->required();
  fos->add_option("--range", fos_range, "LOW HIGH: the slope stands at LOW and fails at HIGH (default 0.5 2)")
      ->expected(2);
  fos->add_option("--steps", fo.steps, "Bisections after the two ends (default 5)");
  fos->add_option("--levels", fo.levels,
                  "Cell sizes h, h/2, ... each bisected alike, 1 to 4 (default 1); 3 or more extrapolate the "
                  "factor to h -> 0");
  fos->add_option("--moved", fo.moved,
                  "Fails: a point moved more than this share of the material's height (default 0.01)");
  fos->add_option("--threads", threads, "OpenMP threads (default: all cores)")->check(CLI::Range(1, 1024));
  fos->add_flag("--overwrite", overwrite, "Replace an earlier study in OUTDIR (removes its files first)");
  fos->add_flag("--force", force, "Run scenarios that need more memory than the machine has");

  std::vector<std::string> measured;
  std::string quantity = "value", unit;
  auto* extrapolate = app.add_subcommand(
      "extrapolate",
      "Richardson's extrapolation of a value measured at three cell sizes or more (Celik et al. 2008)");
  extrapolate
      ->add_option(
          "values", measured,
          "CELL=VALUE per cell size, e.g. 0.5=3.753 0.25=4.123 0.125=4.238 (the three finest are used)")
      ->required();
  extrapolate->add_option("--name", quantity, "What the value is, for the verdict (default \"value\")");
  extrapolate->add_option("--unit", unit, "Its unit, e.g. m");

  skred::BenchOptions bo;
  std::string interp = "gimp", scheme = "averaged", transfer = "flip";
  auto* bench = app.add_subcommand("bench", "Measure particle-updates per second");
  bench
      ->add_option("--problem", bo.problem,
                   "block (elastic, adjustable size) | column (Mohr-Coulomb collapse)")
      ->check(CLI::IsMember({"block", "column"}));
  bench->add_option("--dim", bo.dim, "column: 2 (plane strain) or 3 (a slab 4 cells thick, roller z sides)")
      ->check(CLI::IsMember({2, 3}));
  bench->add_option("--refine", bo.refine, "column: cells per 0.05 m (particles x refine^2)")
      ->check(CLI::Range(1, 20));
  bench->add_option("--particles", bo.particles, "block: approximate number of particles")
      ->check(CLI::Range(100L, 100000000L));
  bench->add_option("--steps", bo.steps, "Timed steps per repeat")->check(CLI::Range(1, 1000000));
  bench->add_option("--repeats", bo.repeats, "Repeats (the median is reported)")->check(CLI::Range(1, 1000));
  bench->add_option("--threads", threads, "OpenMP threads (default: all cores)")->check(CLI::Range(1, 1024));
  bench->add_option("--interpolation", interp, "linear | gimp | gimp-quadrature | bspline")
      ->check(CLI::IsMember({"linear", "gimp", "gimp-quadrature", "bspline"}));
  bench->add_option("--quadrature-points", bo.quadrature_points, "1, 2 or 3")->check(CLI::Range(1, 3));
  bench->add_option("--sort-every", bo.sort_every, "Sort the points by cell every N steps (0: never)")
      ->check(CLI::Range(0L, 1000000000L));
  bench->add_option("--bodies", bo.bodies, "column: 1, or 2 (two halves in frictional contact, mu = tan phi)")
      ->check(CLI::IsMember({1, 2}));
  bench
      ->add_option("--contact-detection", bo.contact_detection,
                   "with --bodies 2: fill | traction ([[contact]] detection)")
      ->check(CLI::IsMember({"fill", "traction"}));
  bench->add_option("--scheme", scheme, "usf | usl | averaged")
      ->check(CLI::IsMember({"usf", "usl", "averaged"}));
  bench->add_option("--velocity-transfer", transfer, "flip | xpic | apic | aflip")
      ->check(CLI::IsMember({"flip", "xpic", "apic", "aflip"}));
  std::string volumetric = "point";
  bench
      ->add_option("--volumetric-strain", volumetric,
                   "point | cell-average (point unless asked: the benches' own setting, not \"auto\")")
      ->check(CLI::IsMember({"point", "cell-average"}));
  bench
      ->add_option("--xpic-period", bo.xpic_period,
                   "xpic: once per this many crossing times h/c (0: every step)")
      ->check(CLI::Range(0.0, 1.0e6));

  skred::PostCommands post(app);  // render, report

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int r = app.exit(e);  // prints help, the version or the error
    return r == 0 ? code::kSuccess : code::kUsage;
  }
  if (post.chosen()) return post.run();
  if (const skred::Launch launch = skred::launched_processes();
      launch.processes > 1 && (*sweep || *refine || *fos)) {
    if (skred::Processes::world().rank() == 0)
      fmt::print(
          stderr,
          "skred: error: started as one of {} processes by an MPI launcher ({}={}); `skred {}` runs in "
          "one process, on all of the machine's cores with OpenMP, and {} copies of it would write the "
          "same results at once. Start it without the launcher (or with -np 1); of the commands, `skred "
          "run`, `skred resume` and `skred bench` run across processes.\n",
          launch.processes, launch.variable, launch.processes,
          *sweep    ? "sweep"
          : *refine ? "refine"
                    : "fos",
          launch.processes);
    return code::kUsage;
  }
  const skred::Processes world = skred::Processes::world();
  ro.processes = world;
  // A failure in one process of several stops them all (the others may wait for it in a
  // collective call), naming the process; a scenario error, the same in each, the first reports.
  const auto fail = [&](int c, const std::string& text) {
    if (!world.distributed()) {
      fmt::print(stderr, "skred: {}\n", text);
      return c;
    }
    if (c == code::kInvalidScenario) {
      if (world.rank() == 0) fmt::print(stderr, "skred: {}\n", text);
      return c;
    }
    fmt::print(stderr, "skred: process {} of {}: {}\n", world.rank(), world.size(), text);
    std::fflush(stderr);
    skred::abort_processes(c);
  };
  try {
    if (*run) {
      ro.restart = restart;
      if (!force) skred::require_fits_machine(scenario);
      return cmd_run(scenario, outdir, threads, ro, overwrite);
    }
    if (*resume) {
      ro.restart = std::filesystem::path(outdir) / "checkpoint.skc";
      return cmd_run((std::filesystem::path(outdir) / "scenario.toml").string(), outdir, threads, ro, false);
    }
    if (scenario_commands.chosen()) return scenario_commands.run();
    if (*sweep) return cmd_sweep(scenario, outdir, sets, threads, overwrite);
    if (*refine) {
      if (!force) rfo.check = [](const skred::AnyScenario& s) { skred::require_fits_machine(s); };
      return cmd_refine(scenario, outdir, rfo, threads, overwrite);
    }
    if (*fos) {
      if (!fos_range.empty()) fo.low = fos_range[0], fo.high = fos_range[1];
      if (!force) fo.check = [](const skred::AnyScenario& s) { skred::require_fits_machine(s); };
      return cmd_fos(scenario, outdir, fo, threads, overwrite);
    }
    if (*extrapolate) {
      try {
        fmt::print("{}", skred::extrapolate_text(measured, quantity, unit));
      } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError("extrapolate", e.what());
      }
      return code::kSuccess;
    }
    if (*bench) {
      if (bo.dim == 3 && bo.problem != "column") {
        fmt::print(stderr, "skred: --dim 3 is available for --problem column only\n");
        return code::kUsage;
      }
      if (bo.bodies == 2 && bo.problem != "column") {
        fmt::print(stderr, "skred: --bodies 2 is available for --problem column only\n");
        return code::kUsage;
      }
      if (bo.bodies == 2 && transfer == "aflip") {  // as scenarios refuse it with [[contact]]
        fmt::print(stderr, "skred: --velocity-transfer aflip is not available with --bodies 2 (contact)\n");
        return code::kUsage;
      }
      if (bo.xpic_period > 0 && transfer != "xpic") {
        fmt::print(stderr, "skred: --xpic-period applies to --velocity-transfer xpic only\n");
        return code::kUsage;
      }
      bo.threads = threads > 0 ? threads : omp_get_max_threads();
      bo.interpolation = interp == "linear"    ? skred::Interpolation::Linear
                         : interp == "gimp"    ? skred::Interpolation::Gimp
                         : interp == "bspline" ? skred::Interpolation::Bspline
                                               : skred::Interpolation::GimpQuadrature;
      bo.scheme = scheme == "usf"   ? skred::StressScheme::USF
                  : scheme == "usl" ? skred::StressScheme::USL
                                    : skred::StressScheme::Averaged;
      bo.velocity_transfer = transfer == "xpic"    ? skred::VelocityTransfer::Xpic
                             : transfer == "apic"  ? skred::VelocityTransfer::Apic
                             : transfer == "aflip" ? skred::VelocityTransfer::Aflip
                                                   : skred::VelocityTransfer::Flip;
      bo.volumetric_averaging = volumetric == "cell-average";
      bo.processes = skred::Processes::world();
      const auto r = skred::run_bench(bo);
      if (bo.processes.rank() != 0) return code::kSuccess;  // (the first process prints)
      fmt::print(
          "bench {}{}{}: {} particles, {} grid nodes, {} steps x {} repeats, {}{} thread(s), {} / {} / {}\n",
          bo.problem, bo.dim == 3 ? " (3D slab, 2x2x2 points per cell)" : "",
          bo.bodies == 2 ? fmt::format(" (two bodies in contact, detection {})", bo.contact_detection) : "",
          r.particles, r.nodes, bo.steps, bo.repeats,
          bo.processes.distributed() ? fmt::format("{} processes x ", bo.processes.size()) : "", bo.threads,
          interp, bo.problem == "column" ? "usf" : scheme,
          transfer + (bo.volumetric_averaging ? " / cell-average" : ""));
      if (bo.problem == "column")
        fmt::print("column: {}, front advanced {:.3f} m in {:.3g} s, {} of {} points yielding\n", r.status,
                   r.runout, bo.steps * 1e-4 * std::min(1.0, 5.0 / bo.refine), r.yielding, r.particles);
      for (double u : r.updates_per_second) fmt::print("  run: {:.3f} M particle-updates/s\n", u / 1e6);
      fmt::print("median: {:.3f} M particle-updates/s ({:.3f} M per thread)\n", r.median / 1e6,
                 r.median / 1e6 / (bo.threads * bo.processes.size()));
      // Above the idle process (code, libraries): what the points and the grid cost.
      // (distributed: the first process's, per point of its share)
      fmt::print("peak memory: {:.1f} MB, {:.1f} MB above the idle process: {:.0f} bytes per particle\n",
                 r.peak_rss_bytes / 1e6, (r.peak_rss_bytes - r.idle_rss_bytes) / 1e6,
                 (r.peak_rss_bytes - r.idle_rss_bytes) / r.own_particles);
      if (bo.threads > 1) fmt::print("OpenMP wait: {}\n", skred::omp_wait_description());
      if (bo.processes.distributed())
        fmt::print(
            "exchanged per step by each process: {:.0f} calls, {:.1f} messages to single processes, "
            "{:.2f} MB (most {:.2f} MB); star forests set up: {:.2f}\n",
            r.calls_per_step, r.messages_per_step, r.bytes_per_step / 1e6, r.most_bytes_per_step / 1e6,
            r.forests_per_step);
      double total = 0.0;
      for (const auto& [name, s] : r.phase_seconds) total += s;
      fmt::print("time per phase (all repeats):\n");
      for (const auto& [name, s] : r.phase_seconds)
        fmt::print("  {:<24} {:8.3f} s  {:5.1f} %\n", name, s, 100.0 * s / total);
    }
  } catch (const skred::CheckpointError& e) {
    return fail(code::kError, e.what());
  } catch (const skred::ScenarioError& e) {
    return fail(code::kInvalidScenario, e.what());
  } catch (const CLI::ValidationError& e) {  // e.g. sweep's --set, checked after parsing
    return fail(code::kUsage, e.what());
  } catch (const std::bad_alloc&) {  // (fuzzing: a run past `ulimit -v` said only "std::bad_alloc")
    return fail(
        code::kError,
        fmt::format("error: out of memory: an allocation failed with {} left to this process (the "
                    "machine's memory, its cgroup's memory.max and the address-space limit, ulimit -v). "
                    "`skred check SCENARIO` estimates what a run needs; coarsen the grid, lower "
                    "particles_per_cell or raise the limit",
                    memory_text(skred::available_memory_bytes())));
  } catch (const std::exception& e) {
    return fail(code::kError, fmt::format("error: {}", e.what()));
  }
  return code::kSuccess;
}

int main(int argc, char** argv) {
  skred::apply_default_omp_wait_policy(argv);  // before any OpenMP call (it may re-execute)
  // Started by an MPI launcher: MPI for every process of the world (parallel/processes.hpp), and
  // MPI_Finalize on every way out of the command.
  if (const skred::Launch launch = skred::launched_processes(); launch.processes > 1) {
    if (!skred::built_with_mpi()) {  // (CMake's SKRED_MPI=OFF: each of the N would write alone)
      if (skred::launched_rank() == 0)
        fmt::print(stderr,
                   "skred: error: started as one of {} processes by an MPI launcher ({}={}), but this "
                   "build of skred has no MPI (configured with cmake -DSKRED_MPI=OFF) and runs in one "
                   "process only. Start it without the launcher, or rebuild with the default "
                   "(-DSKRED_MPI=ON, README) to run across processes.\n",
                   launch.processes, launch.variable, launch.processes);
      return code::kUsage;
    }
    skred::start_processes(&argc, &argv);
  }
  return skred::finish_processes(command(argc, argv));
}
