#include "run/simulation.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/grid_writer.hpp"
#include "io/pvd_writer.hpp"
#include "io/series_writer.hpp"
#include "io/summary_writer.hpp"
#include "io/vtu_writer.hpp"
#include "parallel/point_shares.hpp"
#include "post/elastic_plastic_split.hpp"
#include "post/material_strength.hpp"
#include "run/checkpointing.hpp"
#include "run/density_trigger.hpp"
#include "run/dilation_continuum.hpp"
#include "run/frame_files.hpp"
#include "run/map_files.hpp"
#include "run/memory_use.hpp"
#include "run/point_setup.hpp"
#include "run/run_summary.hpp"
#include "run/slide_measures.hpp"
#include "run/slope_stability.hpp"
#include "run/stability.hpp"
#include "run/version.hpp"
#include "scenario/build.hpp"
#include "scenario/estimate.hpp"
#include "scenario/initial_stress.hpp"
#include "solver/explicit_integrator.hpp"

namespace skred {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Steps of a stage, ceil(duration / dt), at most 1e15 (0 for a NaN). Scenario files are
// refused above 1e9 steps (parser.cpp), but a run set up in code may bring a 1e-300 s step,
// whose step count does not fit a long (converting it, or summing the stages', is undefined).
long stage_step_count(double duration, double dt) {
  constexpr double kMaxStageSteps = 1e15;
  const double n = std::ceil(duration / dt - 1e-9);
  if (!(n > 0.0)) return 0;
  return static_cast<long>(std::min(n, kMaxStageSteps));
}

std::string hms(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = std::lround(seconds);
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60)
                   : fmt::format("{:02}:{:02}", s / 60, s % 60);
}

// series.csv's columns of the [[prescribed_velocity]] forces: force_<name>_<axis>.
template <int D>
std::vector<std::pair<std::string, int>> force_columns(const ScenarioOf<D>& s) {
  std::vector<std::pair<std::string, int>> c;
  for (std::size_t b = 0; b < s.prescribed.size(); ++b)
    for (int d = 0; d < D; ++d)
      c.emplace_back(fmt::format("force_{}_{}", s.prescribed[b].name, "xyz"[d]), static_cast<int>(3 * b) + d);
  return c;
}

template <int D>
SeriesRow series_row(const Integrator<D>& solver, const ParticleTotals<D>& t, long particles, int stage,
                     double runout) {
  const auto& e = solver.energy();
  SeriesRow r{};
  r.step = solver.steps();
  r.time = solver.time();
  r.kinetic_energy = t.kinetic_energy;
  r.strain_energy = e.strain_energy;
  r.gravity_work = e.gravity_work;
  r.plastic_dissipation = e.plastic_dissipation;
  r.friction_work = e.friction_work;
  r.transfer_dissipation = e.transfer_dissipation;
  r.damping_work = e.damping_work;
  r.mean_speed = t.mean_speed;
  r.max_speed = t.max_speed;
  r.momentum_x = t.momentum[0];
  r.momentum_y = t.momentum[1];
  r.num_particles = particles;
  r.stage = stage;
  r.runout = runout;
  r.yielding_points = t.yielding;
  r.contact_work = e.contact_work;
  if constexpr (D == 3) r.momentum_z = t.momentum[2];
  r.iterations = solver.last_step().iterations;
  r.residual = solver.last_step().residual;
  r.load_work = e.load_work;
  r.boundary_force = solver.clock().boundary_force;
  return r;
}

// Copies the scenario file into the output folder as scenario.toml, for the report (post).
void copy_scenario(const std::string& source, const fs::path& outdir) {
  const fs::path target = outdir / "scenario.toml";
  std::error_code ec;
  if (!fs::is_regular_file(source) || fs::equivalent(source, target, ec)) return;
  std::ifstream in(source, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  write_file_atomically(target, [&](std::ostream& os) { os << text.str(); });
}

// The run's integrators, made when a stage first needs one; the current one advances the points.
// A stage of the other kind takes the clock (time, steps, gravity ramp, energies) over from it.
template <int D>
class Integrators {
 public:
  Integrators(const ScenarioOf<D>& s, Particles<D>& P, int threads, const Processes& procs)
      : s_(s), P_(P), threads_(threads), procs_(procs) {}
  Integrator<D>& current() { return *current_; }
  ImplicitSolver<D>* implicit() { return implicit_.get(); }
  ExplicitSolver<D>* explicit_solver() { return explicit_ ? &explicit_->solver() : nullptr; }
  bool is_explicit() const { return current_ == explicit_.get(); }
  // The integrator of stage `st` (its materials at hand-over: the stage's).
  Integrator<D>& use(const Stage& st) {
    Integrator<D>* next = nullptr;
    if (st.integrator == IntegratorKind::Explicit) {
      if (!explicit_) {
        SolverSettings<D> settings = solver_settings(s_);
        settings.processes = procs_;
        explicit_ = std::make_unique<ExplicitIntegrator<D>>(scenario_grid(s_), P_, stage_materials(s_, st),
                                                            settings, threads_);
      }
      next = explicit_.get();
    } else {
      if (!implicit_) {
        ImplicitModel<D> model = implicit_model(s_);
        model.processes = procs_;
        implicit_ =
            std::make_unique<ImplicitSolver<D>>(std::move(model), P_, stage_materials(s_, st), threads_);
      }
      next = implicit_.get();
    }
    if (current_ && next != current_) {
      next->restore(current_->clock(), stage_materials(s_, st));
      next->particles_changed();
    }
    current_ = next;
    return *current_;
  }
  // Wall seconds per phase of every integrator that ran.
  std::vector<std::pair<std::string, double>> phase_seconds() const {
    std::vector<std::pair<std::string, double>> r;
    for (const Integrator<D>* i : {static_cast<const Integrator<D>*>(explicit_.get()),
                                   static_cast<const Integrator<D>*>(implicit_.get())})
      if (i)
        for (auto& ph : i->phase_seconds()) r.push_back(ph);
    return r;
  }

 private:
  const ScenarioOf<D>& s_;
  Particles<D>& P_;
  int threads_;
  Processes procs_;
  std::unique_ptr<ExplicitIntegrator<D>> explicit_;
  std::unique_ptr<ImplicitSolver<D>> implicit_;
  Integrator<D>* current_ = nullptr;
};

}  // namespace

// Scenarios of at least this many points (by the estimate) say what their set-up is doing:
// filling 10^7 points took 34 s in silence (fuzzing).
constexpr double kSetupReportPoints = 1e6;

template <int D>
RunResult run_simulation(const ScenarioOf<D>& s, const fs::path& outdir, const RunOptions& opt) {
  const auto setup_start = Clock::now();
  const double idle_bytes = current_rss_bytes();  // before the points and the grid exist
  const Processes& procs = opt.processes;
  const bool first = procs.rank() == 0;  // writes the run's files and reports
  const bool report_setup = first && opt.progress && estimate_size(s).points >= kSetupReportPoints;
  const auto setup = [&](const std::string& what) {
    if (!report_setup) return;
    fmt::print(stderr, "set-up: {} ({:.1f} s)\n", what,
               std::chrono::duration<double>(Clock::now() - setup_start).count());
    std::fflush(stderr);
  };
  setup(fmt::format("filling the bodies with about {:.3g} points", estimate_size(s).points));
  // Thesis eq. 5.6-5.7 (initial stress); across processes each builds about its share.
  Particles<D> particles = build_points(s, procs, setup);
  // That peak is the set-up's (summary.json's processes.setup_peak_bytes), the run's memory is
  // what it holds after (one process: both). The blocks before the first map, so that each
  // process touches only its own block of the grid.
  repartition_in_blocks(particles, scenario_grid(s), procs);
  double setup_peak = procs.distributed() ? peak_rss_bytes() : 0.0;
  // (glibc keeps freed pages for reuse: the others' points' and the moved points' go back)
  if (procs.distributed()) release_free_memory();
  if (procs.distributed() && !reset_peak_rss()) setup_peak = 0.0;
  procs.max(&setup_peak, 1);
  Integrators<D> integrators(s, particles, opt.threads, procs);
  Integrator<D>* solver = &integrators.use(s.stages.front());

  if (first) {
    fs::create_directories(outdir);
    copy_scenario(s.source, outdir);
  }
  procs.barrier();                                       // the folder exists for every process
  const fs::path written = first ? outdir : fs::path();  // the others only count (io/pvd_writer.hpp)
  PvdWriter pvd(written);
  PvdWriter grid_pvd(written, "grid.pvd");  // post: grid node fields per frame
  // Strength of the current stage's materials (as plastic, also in an elastic stage), for the
  // relative yield function; Fe and the stress recomputed from it (Post eq. 67-77).
  std::vector<MaterialStrength> strength = material_strengths(s.materials);
  std::vector<Mat3> elastic_F;
  std::vector<Sym3> stress_from_Fe;
  const bool damped =
      std::any_of(s.stages.begin(), s.stages.end(), [](const Stage& st) { return st.local_damping > 0.0; });
  // Stage::rest_measure: a stage whose rest test reads the material's speed
  const bool material_speed = std::any_of(s.stages.begin(), s.stages.end(), [&](const Stage& st) {
    return rest_measure_of(s, st) == Stage::RestMeasure::Material;
  });
  SeriesWriter series(first ? outdir / "series.csv" : fs::path(),
                      {.momentum_z = D == 3,
                       .contact_work = solver_settings(s).contact.enabled(),
                       .damping_work = damped,
                       .material_speed = material_speed,
                       .implicit = s.any_implicit(),
                       .forces = force_columns(s)});
  RunProgress<D> at;  // where the run stands: saved in checkpoints (run/checkpointing.hpp)
  Checkpointing<D> checkpoints(s, outdir, opt);
  if (!checkpoints.restore(particles, *solver, at, series, pvd, grid_pvd)) {
    if constexpr (D == 3) at.maps = start_hazard_maps(s, particles, procs);  // run/hazard_maps.hpp
  } else {                                                                   // (not in checkpoints)
    at.tracker.set_processes(procs);
    at.maps.set_processes(procs);
    solver->particles_changed();
  }
  std::vector<Sym3> smoothed;
  const VtuOptions vtu_options{s.output_fields, s.output_compression};
  const bool wants_split = output_fields::wants_elastic_split(s.output_fields);
  auto write_frame = [&]() {
    const int frame = static_cast<int>(at.frame_times.size());
    at.frame_times.push_back(solver->time());
    solver->smoothed_stress(smoothed);
    write_grid_frame(*solver, outdir, frame, grid_pvd, s.output_compression,
                     first);  // post: after smoothed_stress()
    ParticleFields extra;
    extra.smoothed_stress = &smoothed;
    extra.strength = &strength;  // post: relative yield
    if (wants_split) {           // Fe, Fp or stress_from_Fe is written
      elastic_F.resize(particles.size());
      stress_from_Fe.resize(particles.size());
      for (std::size_t p = 0; p < particles.size(); ++p) {
        elastic_F[p] = embed3<D>(particles.Fe[p], 1.0);
        const auto& mat = solver->materials()[static_cast<std::size_t>(particles.material[p])];
        stress_from_Fe[p] = stress_from_elastic_F(full_stress<D>(particles.reference_stress(p)), elastic_F[p],
                                                  mat.elastic_constants);
      }
      extra.elastic_F = &elastic_F;
      extra.stress_from_elastic_F = &stress_from_Fe;
    }
    std::string name = fmt::format("particles_{:06}.vtu", frame);
    if (procs.distributed())
      name = write_frame_pieces(outdir, frame, particles, extra, vtu_options, procs);
    else
      write_particles_vtu(outdir / name, particles, extra, vtu_options);
    pvd.add(solver->time(), name);
    series.flush();
  };

  const DilationContinua dilation(s);  // Paper III §C.3.2 (empty without dilated continua)
  SplitSettings split = s.splitting;   // Thesis §3.4 (its cap set per step when distributed)
  // The explicit stages' time step; an implicit stage takes its own (stage_time_step).
  const double explicit_dt = scenario_time_step(s);
  // The instability detector (run/stability.hpp): a step above the stable limit stops the run
  // before it starts; afterwards every series row and every frame is checked.
  StabilityWatch<D> watch(s, explicit_dt, solver->totals().mass, procs);
  StepStatus unstable;     // ok, or the point and reason found by the detector
  long unstable_step = 0;  // the step after which it was found
  bool left_grid = false;
  bool not_converged = false;  // an implicit step did not converge (after its cuts)
  auto stop_unstable = [&](std::string reason, long p) {
    unstable = {false, p, std::move(reason)};
    unstable_step = solver->steps();
  };
  if (std::string why = watch.unusable_step(); !why.empty())  // name a point if one is the cause
    stop_unstable(std::move(why), watch.initial_speed_finite() ? -1 : offending_point(particles, procs));
  else if (std::string above = watch.step_above_limit(); !above.empty() && !s.allow_unstable_time_step)
    stop_unstable(std::move(above), -1);
  long total_steps = 0;  // upper bound: every stage to its full duration
  if (unstable.ok)
    for (const Stage& st : s.stages) total_steps += stage_step_count(st.duration, stage_time_step(s, st));
  const bool tty = isatty(fileno(stderr));
  long points = procs.sum_of(static_cast<long>(particles.size()));  // of all processes, at the last row
  RunResult res;

  const auto start = Clock::now();
  const Exchanged traffic_start = exchanged();  // (this process's, from here to the run's end)
  const long steps_start = solver->steps();
  double compute_seconds = 0.0;
  long computed_updates = 0;  // point updates stepped here (the point count may change)
  long rebalances = 0;        // the repartitions that moved points (processes)
  long shown_updates = 0;     // and by all processes, as the progress line counts them
  auto last_report = start;
  StepStatus status;
  bool stopped = false;  // by a signal, after a checkpoint
  bool moved = false;    // a point of opt.stop_stage moved further than opt.stop_moved allows
  for (std::size_t k = at.stage; k < s.stages.size() && status.ok && unstable.ok && !stopped; ++k) {
    const Stage& st = s.stages[k];
    Stage as_plastic = st;
    as_plastic.elastic = false;
    strength = material_strengths(stage_materials(s, as_plastic));
    const double dt = stage_time_step(s, st);
    const long stage_steps = stage_step_count(st.duration, dt);
    const bool begins = !at.in_stage;  // false for the stage a restart continues
    const Stage::RestMeasure measure = rest_measure_of(s, st);
    solver = &integrators.use(st);
    const bool implicit = st.integrator == IntegratorKind::Implicit;
    // A quasi-static stage's points are at rest by construction: it ends with its load steps.
    const bool rests = !(implicit && st.implicit.analysis == ImplicitAnalysis::QuasiStatic);
    const double stage_end = (begins ? solver->time() : at.stage_start) + st.duration;
    if (implicit) integrators.implicit()->set_stage(st.implicit, dt, stage_end);
    solver->set_local_damping(st.local_damping);
    if (begins) {
      solver->begin_stage(stage_materials(s, st), st.gravity_ramp_time);
      at.stage = k;
      at.in_stage = true;
      at.stage_first_step = solver->steps();
      at.stage_start = solver->time();
      at.tracker = StageTracker<D>(st.name, particles, at.stage_start, solver->totals().kinetic_energy,
                                   st.rest_speed, st.rest_time, s.origin[0], s.cell_size,
                                   s.cells[0] * s.cell_size, st.runout_thickness, s.origin[D - 1],
                                   D == 3 ? s.cells[D - 1] * s.cell_size : 0.0, procs);
      if (measure != Stage::RestMeasure::Displacement) particles.x_rest = {};  // (its first row starts one)
      if constexpr (D == 3) at.maps.begin_stage(particles, at.stage_start);
    }
    const long first_step = at.stage_first_step;
    const double stage_start = at.stage_start;
    StageTracker<D>& tracker = at.tracker;
    DensityTrigger density(s, k);  // Paper III §C.3 trigger
    watch.begin_stage(tracker.kinetic_start(), stored_stress_energy(particles, solver->materials(), procs));
    auto sample = [&]() {
      const ParticleTotals<D> t = solver->totals();
      points = procs.sum_of(static_cast<long>(particles.size()));
      SeriesRow row = series_row(*solver, t, points, static_cast<int>(k), tracker.runout(particles));
      if (material_speed) row.material_speed = solver->material_mean_speed();
      if constexpr (D == 3) at.maps.sample(particles, solver->time());
      series.add(row);
      if (std::string why = watch.check(t, solver->energy()); !why.empty())
        stop_unstable(std::move(why), offending_point(particles, procs));
      else if (watch.observe_dilation(particles) && first)  // once, when the limit is first passed
        fmt::print(stderr, "{}warning at t = {:.4g} s: {}\n", tty ? "\n" : "", solver->time(),
                   watch.dilation_note());
      const bool ramping = solver->time() - stage_start < 0.5 * st.gravity_ramp_time ||
                           solver->time() - stage_start < density.ramp_end();
      const bool rest =
          measure == Stage::RestMeasure::Displacement
              ? tracker.observe_window(particles, solver->time(), t.mean_speed)
              : tracker.observe(solver->time(), t.mean_speed,
                                measure == Stage::RestMeasure::Material ? row.material_speed : t.mean_speed);
      return rest && !ramping;
    };
    if (begins) sample();
    if (begins && k == 0 && unstable.ok) {
      setup("the first frame");
      write_frame();
      setup("done; the time loop starts");
      at.next_output = s.output_interval;
      at.next_series = s.series_interval;
    }
    std::string ended_by = unstable.ok ? "duration" : "unstable";
    // Explicit stages run their count of steps; implicit ones until their end time (a cut step
    // covers less).
    auto stage_done = [&]() {
      return implicit ? solver->time() >= stage_end - 1e-9 * dt : solver->steps() - first_step >= stage_steps;
    };
    while (unstable.ok && !stage_done()) {
      // Point order and point changes between steps (docs/method.md, "Point order").
      // Split among processes, the points are kept in blocks of the grid (point_shares.hpp).
      if (solver->steps() % (opt.sort_every > 0 ? opt.sort_every : kSortEvery) == 0 &&
          repartition_in_blocks(particles, solver->grid(), procs)) {
        solver->particles_changed();
        ++rebalances;
      }
      if (opt.sort_every > 0 && solver->steps() % opt.sort_every == 0 &&
          particles.sort_by_cell(solver->grid(), solver->sort_by_nearest_node(), solver->threads()))
        solver->particles_changed();
      if constexpr (D == 2)  // the test hook that adds and removes points (2D runs)
        if (opt.edit_points && integrators.is_explicit() &&
            opt.edit_points(particles, *integrators.explicit_solver()))
          solver->particles_changed();
      if (!density.empty() && density.apply(particles, solver->time() - stage_start))
        solver->particles_changed();
      if (!dilation.empty())  // Paper III §C.3.2: dilated points join the new continuum
        if (const long moved = procs.sum_of(dilation.apply(particles, solver->threads())); moved > 0) {
          tracker.dilated(moved, solver->time());
          solver->particles_changed();
        }
      if (!split.body_splits.empty()) {  // Thesis §3.4
        if (procs.distributed() &&
            s.splitting.max_points > 0) {  // the cap is the run's: a share of what is left
          const long own = static_cast<long>(particles.size()),
                     left = s.splitting.max_points - procs.sum_of(own);
          split.max_points = own + std::max(0L, left) / procs.size();
        }
        if (split_points(particles, split) > 0) solver->particles_changed();
        if (procs.distributed() && share_imbalance(particles, procs) > split.rebalance_above) {
          if (repartition_in_blocks(particles, solver->grid(), procs)) {  // (split points land unevenly)
            solver->particles_changed();
            ++rebalances;
          }
        }
      }
      const auto t0 = Clock::now();
      status = solver->step();
      compute_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
      if (!status.ok) {
        left_grid = left_the_grid(particles, status.particle, solver->grid(), watch.speed_bound(), procs);
        not_converged = implicit && status.particle < 0;
        ended_by = left_grid ? "left_grid" : not_converged ? "not_converged" : "unstable";
        break;
      }
      computed_updates += static_cast<long>(particles.size());
      shown_updates += points;
      const double t = solver->time();
      const bool last = stage_done();
      bool at_rest = false;
      if (t >= at.next_series - 0.5 * dt || last) {
        at_rest = sample() && rests;
        while (at.next_series <= t + 0.5 * dt) at.next_series += s.series_interval;
        moved = static_cast<int>(k) == opt.stop_stage &&
                tracker.max_displacement_of(particles) > opt.stop_moved * tracker.height_start();
      }
      const bool frame = t >= at.next_output - 0.5 * dt || last || at_rest || moved;
      if (frame && unstable.ok)  // a frame must not hold a non-finite value
        if (const long p = first_non_finite_point(particles, procs); p >= 0)
          stop_unstable("non-finite position, velocity, deformation gradient or stress", p);
      if (!unstable.ok) {
        ended_by = "unstable";
        break;
      }
      if (frame) {
        write_frame();
        while (at.next_output <= t + 0.5 * dt) at.next_output += s.output_interval;
      }
      const auto now = Clock::now();
      if (first && opt.progress &&
          (now - last_report > std::chrono::seconds(tty ? 1 : 10) || last || at_rest || moved)) {
        last_report = now;
        const double elapsed = std::chrono::duration<double>(now - start).count();
        const double frac = std::min(1.0, static_cast<double>(solver->steps()) / total_steps);
        const double pups = compute_seconds > 0 ? shown_updates / compute_seconds : 0.0;
        const StepReport rep = solver->last_step();
        const std::string newton =
            implicit ? fmt::format("  {} iterations (residual {:.1e}){}", rep.iterations, rep.residual,
                                   rep.cuts > 0 ? fmt::format(", cut {}x", rep.cuts) : "")
                     : fmt::format("  {:.2f} M particle-updates/s", pups / 1e6);
        fmt::print(stderr, "{}stage {} ({}{})  {} {}  t = {:.4g} s  {:5.1f} %  ETA {}{}{}", tty ? "\r" : "",
                   k + 1, st.name, implicit ? ", implicit" : "", implicit ? "load step" : "step",
                   solver->steps(), t, 100 * frac, hms(elapsed / frac - elapsed), newton,
                   tty && !(last || at_rest || moved) ? "" : "\n");
        std::fflush(stderr);
      }
      if (at_rest || moved) {
        ended_by = moved ? "moved" : "rest";
        break;
      }
      if (checkpoints.after_step(particles, *solver, at, series)) {  // periodic; stop on a signal
        stopped = true;
        break;
      }
    }
    if (stopped) break;
    const ParticleTotals<D> t = solver->totals();
    const EnergyTotals& e = solver->energy();
    at.finished.push_back(tracker.finish(particles, solver->time(), solver->steps() - first_step,
                                         t.kinetic_energy, e.gravity_work, e.strain_energy,
                                         e.plastic_dissipation, ended_by));
    at.finished.back().rest_measure = to_string(measure);
    if constexpr (D == 3) finish_stage_maps(s, particles, at.maps, k, outdir, at.map_files);
    at.in_stage = false;
    at.stage = k + 1;
    if (moved) break;  // the stages after it do not run
  }
  const long own = static_cast<long>(particles.size());
  const long n = procs.sum_of(own);
  res.particles = n;
  res.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  res.steps = solver->steps();
  res.simulated_time = solver->time();
  procs.max(&compute_seconds, 1);  // (the slowest process's)
  computed_updates = procs.sum_of(computed_updates);
  res.particle_updates_per_second = compute_seconds > 0 ? computed_updates / compute_seconds : 0.0;
  if (!status.ok) unstable_step = solver->steps() + 1;  // the step that failed
  if (status.ok) status = unstable;
  res.completed = status.ok && !stopped;
  res.interrupted = stopped;
  res.left_grid = left_grid;
  if (!status.ok) {
    const long p = status.particle;
    const std::string note = watch.dilation_note();  // when dilated material is the likely cause
    const PointPlace<D> place = p < 0 ? PointPlace<D>{} : point_place(particles, p, procs);
    const std::string where =
        place.body < 0 ? std::string()
                       : fmt::format(": particle {} of body '{}' at ({:.6g}, {:.6g}{})", p,
                                     s.bodies[static_cast<std::size_t>(place.body)].name, place.x[0],
                                     place.x[1], D == 3 ? fmt::format(", {:.6g}", place.x[D - 1]) : "");
    res.message = not_converged ? fmt::format("stopped at step {} (t = {:.6g} s): {}", unstable_step,
                                              solver->time(), status.reason)
                  : left_grid
                      ? fmt::format(
                            "stopped at step {} (t = {:.6g} s){} left the grid (its state is "
                            "sound: enlarge the grid or close its sides)",
                            unstable_step, solver->time(), where)
                      : fmt::format("unstable at step {} (t = {:.6g} s){}: {}{}", unstable_step,
                                    solver->time(), where, status.reason, note.empty() ? "" : "; " + note);
    write_frame();  // the last state, for diagnosis
  } else if (stopped) {
    res.message =
        fmt::format("interrupted at step {} (t = {:.6g} s); continue with: {}skred resume {}",
                    solver->steps(), solver->time(),
                    procs.distributed() ? fmt::format("mpirun -np {} ", procs.size()) : "", outdir.string());
    write_frame();  // the state at the checkpoint
  } else {
    checkpoints.at_end(particles, *solver, at, series);
  }
  series.flush();
  double peak = peak_rss_bytes(), above_idle = peak - idle_bytes;  // (all processes': a sum)
  procs.sum(&peak, 1);
  procs.sum(&above_idle, 1);
  const long share_min = procs.min(own), share_max = procs.max(own);
  // The most any process exchanged per step (frames and rebalances included).
  double traffic[2] = {exchanged().bytes - traffic_start.bytes,
                       static_cast<double>(exchanged().messages - traffic_start.messages)};
  procs.max(traffic, 2);
  std::vector<std::string> run_maps;
  if constexpr (D == 3)
    if (at.maps.enabled() && !stopped)  // the run's maps (a resumed run writes them at its end)
      run_maps = write_map_set(s, at.maps, at.maps.run(), outdir, "maps");
  res.stages = at.finished;
  if (!first) return res;

  Summary sum{};
  sum.status = stopped         ? "interrupted"
               : status.ok     ? "completed"
               : left_grid     ? "left_grid"
               : not_converged ? "not_converged"
                               : "unstable";
  sum.message = res.message;
  sum.steps = res.steps;
  sum.simulated_time = res.simulated_time;
  sum.end_time = s.end_time;
  sum.particles = n;
  sum.cells = s.cell_count();
  sum.dimension = D;
  sum.wall_seconds = res.wall_seconds;
  sum.particle_updates_per_second = res.particle_updates_per_second;
  sum.peak_memory_bytes = peak;
  if (n > 0 && sum.peak_memory_bytes > 0.0 && idle_bytes > 0.0)
    sum.memory_bytes_per_point = above_idle / static_cast<double>(n);
  sum.threads = solver->threads();
  sum.processes = procs.size();
  sum.setup_peak_bytes = setup_peak;
  sum.rebalances = rebalances;
  sum.share_min = share_min;
  sum.share_max = share_max;
  if (const long taken = res.steps - steps_start; taken > 0) {
    sum.bytes_per_step = traffic[0] / static_cast<double>(taken);
    sum.messages_per_step = traffic[1] / static_cast<double>(taken);
  }
  res.limit_equilibrium = describe_scenario(sum, s, n);
  sum.time_step = explicit_dt;
  if (ImplicitSolver<D>* im = integrators.implicit()) describe_implicit(sum, s, *im);
  sum.stages = at.finished;
  if constexpr (D == 3)
    if (at.maps.enabled() && !stopped) {
      sum.maps = at.map_files;
      for (std::string& f : run_maps) sum.maps.push_back(f);
    }
  sum.phase_seconds = integrators.phase_seconds();
  sum.version = version();
  sum.git_commit = git_commit();
  write_summary_json(outdir / "summary.json", sum);
  return res;
}

RunResult run_simulation(const AnyScenario& s, const fs::path& outdir, const RunOptions& opt) {
  return std::visit([&](const auto& sc) { return run_simulation(sc, outdir, opt); }, s);
}

template RunResult run_simulation<2>(const Scenario&, const fs::path&, const RunOptions&);
template RunResult run_simulation<3>(const Scenario3&, const fs::path&, const RunOptions&);

}  // namespace skred
