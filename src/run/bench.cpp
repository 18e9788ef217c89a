#include "run/bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "parallel/point_shares.hpp"
#include "run/memory_use.hpp"
#include "run/simulation.hpp"
#include "run/slide_measures.hpp"
#include "scenario/build.hpp"
#include "scenario/estimate.hpp"
#include "scenario/initial_stress.hpp"
#include "solver/explicit_solver.hpp"

namespace skred {

namespace {

// One step, preceded by a sort of the points by cell when the step number is a multiple of
// `every` (the rule of run_simulation, docs/method.md "Point order").
template <int D>
StepStatus sorted_step(Particles<D>& P, ExplicitSolver<D>& solver, long every) {
  if (solver.steps() % (every > 0 ? every : kSortEvery) == 0 &&
      repartition_in_blocks(P, solver.grid(), solver.processes()))  // (split among processes)
    solver.particles_changed();
  if (every > 0 && solver.steps() % every == 0 &&
      P.sort_by_cell(solver.grid(), solver.sort_by_nearest_node(), solver.threads()))
    solver.particles_changed();
  return solver.step();
}

std::vector<double> sorted(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v;
}

// Adds the phase times of the timed steps (the timer's `after` less `before`) to res.
// The exchange per step since `before`, over `steps` steps: the processes' mean and most
// (collective; an end slab or block has fewer neighbours than one in the middle).
void count_exchange(BenchResult& res, const Exchanged& before, int steps, const Processes& procs) {
  const Exchanged now = exchanged();
  res.calls_per_step = static_cast<double>(now.calls - before.calls) / std::max(steps, 1);
  double messages = static_cast<double>(now.messages - before.messages) / std::max(steps, 1);
  procs.sum(&messages, 1);
  res.messages_per_step = messages / procs.size();
  res.forests_per_step = static_cast<double>(now.forests - before.forests) / std::max(steps, 1);
  double bytes = (now.bytes - before.bytes) / std::max(steps, 1), most = bytes;
  procs.sum(&bytes, 1);
  procs.max(&most, 1);
  res.bytes_per_step = bytes / procs.size();
  res.most_bytes_per_step = most;
}

void add_phases(BenchResult& res, const PhaseTimer& before, const PhaseTimer& after) {
  for (std::size_t k = 0; k < PhaseTimer::kCount; ++k) {
    const Phase p = static_cast<Phase>(k);
    const double s = after.seconds(p) - before.seconds(p);
    if (s <= 0.0) continue;
    auto it = std::find_if(res.phase_seconds.begin(), res.phase_seconds.end(),
                           [&](const auto& e) { return e.first == phase_name(p); });
    if (it == res.phase_seconds.end())
      res.phase_seconds.emplace_back(phase_name(p), s);
    else
      it->second += s;
  }
}

// The Mohr-Coulomb column collapse, built through the scenario parser like a user's file. In
// 3D (dim = 3) the same column as a slab kSlabCells cells thick between roller z walls,
// 2 x 2 x 2 points per cell (the plane-strain problem again, tests/test_column_3d.cpp).
constexpr int kSlabCells = 4;

std::string column_text(const BenchOptions& opt) {
  const double h = 0.05 / opt.refine;
  const bool d3 = opt.dim == 3;
  const std::string z = d3 ? fmt::format(", {}", kSlabCells * h) : "", z0 = d3 ? ", 0.0" : "";
  // One body, or its lower and upper halves in contact with mu = tan(30 deg) (--bodies 2).
  auto body = [&](const char* name, double y0, double y1) {
    return fmt::format(
        "[[body]]\nname = \"{}\"\nmaterial = \"soil\"\nparticles_per_cell = 2\n"
        "shape = \"{}\"\nmin = [0.0, {}{}]\nmax = [2.0, {}{}]\n",
        name, d3 ? "box" : "rectangle", y0, z0, y1, z);
  };
  const std::string bodies =
      opt.bodies == 2 ? body("lower", 0.0, 2.0) + body("upper", 2.0, 4.0) +
                            "[[contact]]\nbodies = [\"lower\", \"upper\"]\nfriction = 0.5773502691896258\n" +
                            fmt::format("detection = \"{}\"\n", opt.contact_detection)
                      : body("column", 0.0, 4.0);
  return fmt::format(
      R"(
[grid]
size = [10.0, 4.5{2}]
cell_size = {0}
[[material]]
name = "soil"
model = "mohr-coulomb"
density = 1800.0
young = 10e6
poisson = 0.3
friction = 30.0
cohesion = 500.0
{7}
[initial_stress]
k0 = "poisson"
[gravity]
acceleration = [0.0, -9.81{3}]
[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"
{5}
[solver]
interpolation = "{1}"
quadrature_points = {6}
scheme = "usf"
time_step = {8}
end_time = 1.0
)",
      h, to_string(opt.interpolation), z, z0, d3 ? "box" : "rectangle",
      d3 ? "z_min = \"roller\"\nz_max = \"roller\"" : "", opt.quadrature_points, bodies,
      // 0.1 ms up to refine 5; finer, the stable step's share (refine 8: 10^6 points in 3D, 0.8 M in 2D)
      1e-4 * std::min(1.0, 5.0 / opt.refine));
}

template <int D>
BenchResult run_column(const BenchOptions& opt) {
  const ScenarioOf<D> s = std::get<ScenarioOf<D>>(parse_any_scenario(column_text(opt), "bench-column"));
  BenchResult res;
  for (int r = 0; r < opt.repeats; ++r) {
    Particles<D> P = build_particles(s);
    apply_initial_stress(s, P);
    const GridGeometry<D> grid = scenario_grid(s);
    keep_share(P, opt.processes);
    repartition_in_blocks(P, grid, opt.processes);  // (the set-up's: not timed)
    SolverSettings<D> st = solver_settings(s);
    st.processes = opt.processes;
    st.velocity_transfer = opt.velocity_transfer;
    st.xpic_period = opt.xpic_period * stable_time_step(s);  // seconds
    st.volumetric_averaging = opt.volumetric_averaging;
    ExplicitSolver<D> solver(grid, P, stage_materials(s, s.stages[0]), st, opt.threads);
    const SurfaceProfile before =
        start_profile(P, 0.0, s.cell_size, s.cells[0], 0.5 * s.cell_size, 0, -INFINITY, opt.processes);
    const PhaseTimer before_phases = solver.phase_times();
    const Exchanged sent = exchanged();
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < opt.steps; ++k)
      if (!sorted_step(P, solver, opt.sort_every).ok) {
        res.status = fmt::format("unstable at step {}", k + 1);
        break;
      }
    double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    count_exchange(res, sent, opt.steps, opt.processes);
    opt.processes.max(&sec, 1);  // the slowest process's
    res.own_particles = static_cast<long>(P.size());
    res.particles = opt.processes.sum_of(res.own_particles);
    res.nodes = static_cast<long>(grid.node_count());
    res.updates_per_second.push_back(static_cast<double>(res.particles) * solver.steps() / sec);
    res.runout = runout_of(before, P, 0.0, s.cell_size, 0.5 * s.cell_size, 0, -INFINITY, opt.processes).x_max;
    res.yielding = solver.totals().yielding;
    add_phases(res, before_phases, solver.phase_times());
  }
  return res;
}

}  // namespace

BenchResult run_bench(const BenchOptions& opt) {
  const double idle = current_rss_bytes();  // before any point or node exists
  if (opt.problem == "column") {
    BenchResult res = opt.dim == 3 ? run_column<3>(opt) : run_column<2>(opt);
    res.median = sorted(res.updates_per_second)[res.updates_per_second.size() / 2];
    res.peak_rss_bytes = peak_rss_bytes();
    res.idle_rss_bytes = idle;
    return res;
  }
  // A block filling the lower three quarters of a square box, 4 points per cell.
  const int cells = std::max(4, static_cast<int>(std::lround(std::sqrt(opt.particles / 3.0))));
  const double h = 0.1;
  GridGeometry<2> grid;
  grid.h = h;
  grid.cells = {cells, cells};
  Material soil;
  soil.name = "soil";
  soil.density = 2000.0;
  soil.elastic = {20e6, 0.3};

  BenchResult res;
  for (int r = 0; r < opt.repeats; ++r) {
    Particles<2> P;
    const int rows = (3 * cells) / 4;
    P.reserve(static_cast<std::size_t>(4) * cells * rows);
    const double q = h / 2, vol = q * q;
    for (int j = 0; j < 2 * rows; ++j)
      for (int i = 0; i < 2 * cells; ++i)
        P.add(Vec<2>((i + 0.5) * q, (j + 0.5) * q), Vec<2>::Zero(), soil.density * vol, vol,
              Vec<2>(q / 2, q / 2), 0, 0);
    keep_share(P, opt.processes);
    repartition_in_blocks(P, grid, opt.processes);
    SolverSettings<2> st;
    st.processes = opt.processes;
    st.interpolation = opt.interpolation;
    st.quadrature_points = opt.quadrature_points;
    st.scheme = opt.scheme;
    st.velocity_transfer = opt.velocity_transfer;
    st.xpic_period = opt.xpic_period * h / soil.wave_speed();
    st.volumetric_averaging = opt.volumetric_averaging;
    st.dt = 0.3 * h / soil.wave_speed();
    st.gravity = Vec<2>(0.0, -9.81);
    st.boundaries = {BoundarySide{BoundaryKind::Roller, 0}, BoundarySide{BoundaryKind::Roller, 0},
                     BoundarySide{BoundaryKind::Fixed, 0}, BoundarySide{BoundaryKind::Free, 0}};
    ExplicitSolver<2> solver(grid, P, {soil}, st, opt.threads);
    sorted_step(P, solver, opt.sort_every);  // warm-up (first touch of the grid and buffers)
    const PhaseTimer before_phases = solver.phase_times();
    const Exchanged sent = exchanged();
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < opt.steps; ++s) sorted_step(P, solver, opt.sort_every);
    double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    count_exchange(res, sent, opt.steps, opt.processes);
    opt.processes.max(&sec, 1);  // the slowest process's
    res.own_particles = static_cast<long>(P.size());
    res.particles = opt.processes.sum_of(res.own_particles);
    res.nodes = static_cast<long>(grid.node_count());
    res.updates_per_second.push_back(static_cast<double>(res.particles) * opt.steps / sec);
    add_phases(res, before_phases, solver.phase_times());
  }
  res.median = sorted(res.updates_per_second)[res.updates_per_second.size() / 2];
  res.peak_rss_bytes = peak_rss_bytes();
  res.idle_rss_bytes = idle;
  return res;
}

}  // namespace skred
