// `skred run` split among processes (issue 55), under `mpirun -np 2` (and 4 by hand): a short
// two-stage slide run whole by run_simulation, its series.csv, stage measures, frames and final
// points against one process's run of it (within 1e-12, relative); a checkpoint in pieces resumed
// on the same count (bit for bit) and on another (within round-off); a 3D column with its hazard
// maps; the implicit R6 cylinder, at the points and with Acosta's DM-GC (within the solver's
// tolerance). The first process runs the one-process references and compares.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../support.hpp"
#include "parallel/processes.hpp"
#include "run/checkpointing.hpp"
#include "run/simulation.hpp"
#include "scenario/scenario.hpp"

namespace skred {
namespace {

namespace fs = std::filesystem;

// A 4.5 m slope at 35 deg over a 1 m base layer, held elastic under gravity, then Mohr-Coulomb
// with phi = 10 deg and little cohesion: it slides, 0.8 m of runout in the second stage's 1 s.
constexpr const char* kSlope = R"(
title = "small slope for the distributed run"
[grid]
size = [16.0, 6.0]
cell_size = 0.5
[[material]]
name = "soil"
model = "mohr-coulomb"
density = 2000.0
young = 40.0e6
poisson = 0.42
friction = 10.0
cohesion = 200.0
dilation = 0.0
[[body]]
name = "slope"
material = "soil"
particles_per_cell = 3
shape = "polygon"
vertices = [[0.0, 0.0], [16.0, 0.0], [16.0, 1.0], [9.0, 1.0], [4.0, 4.5], [0.0, 4.5]]
[gravity]
acceleration = [0.0, -9.81]
[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"
[solver]
interpolation = "gimp"
scheme = "usf"
cfl = 0.4
velocity_transfer = "xpic"
xpic_period = 2.0
volumetric_strain = "cell-average"
[[stage]]
name = "equilibrium"
duration = 0.2
gravity_ramp_time = 0.15
elastic = true
[[stage]]
name = "slide"
duration = 1.0
[output]
interval = 0.1
series_interval = 0.01
)";

// The columns of a series.csv: column name -> values.
std::map<std::string, std::vector<double>> read_series(const fs::path& file) {
  std::map<std::string, std::vector<double>> cols;
  for (const auto& row : test::series_rows(file))
    for (const auto& [name, value] : row) cols[name].push_back(value);
  return cols;
}

// The series of two runs column by column, each within `tol` of its kind's largest magnitude: the
// energies' (a sum of terms that cancel, or a term near zero, is compared against the energies
// it is made of), the momenta's (a component near zero against the one gravity drives), or the
// column's own.
std::string kind_of(const std::string& column) {
  for (const char* end : {"_energy", "_work", "_dissipation"})
    if (column.ends_with(end)) return "energy";
  return column.starts_with("momentum_") ? "momentum" : column;
}

void expect_same_series(const fs::path& a, const fs::path& b, double tol, const std::string& what) {
  const auto one = read_series(a), all = read_series(b);
  ASSERT_FALSE(one.empty()) << what << ": " << a;
  ASSERT_EQ(one.size(), all.size()) << what;
  std::map<std::string, double> scales;
  for (const auto& [name, ref] : one)
    for (double x : ref) scales[kind_of(name)] = std::max(scales[kind_of(name)], std::abs(x));
  for (const auto& [name, ref] : one) {
    const std::vector<double>& v = all.at(name);
    ASSERT_EQ(v.size(), ref.size()) << what << ": rows of " << name;
    if (name == "residual") {  // an implicit step's: converged, round-off below the tolerance; with
                               // Acosta's load stepping, the out-of-balance force it carries on
      for (std::size_t i = 0; i < ref.size(); ++i) {
        if (std::max(v[i], ref[i]) <= 1e-8) continue;
        EXPECT_LE(std::abs(v[i] - ref[i]), tol * ref[i]) << what << ": residual row " << i;
      }
      continue;
    }
    const double scale = scales[kind_of(name)];
    for (std::size_t i = 0; i < ref.size(); ++i)
      EXPECT_LE(std::abs(v[i] - ref[i]), tol * scale) << what << ": " << name << " row " << i;
  }
}

// The points of a run's last checkpoint (in pieces or whole), sorted by where they started.
template <int D>
std::vector<std::pair<Vec<D>, Vec<D>>> final_points(const ScenarioOf<D>& s, const fs::path& outdir) {
  Particles<D> P;
  SolverClock c;
  RunProgress<D> at;
  std::vector<SeriesRow> rows;
  if (fs::exists(checkpoint_manifest(outdir))) {  // "processes N" on its second line
    const std::string m = test::file_text(checkpoint_manifest(outdir));
    const int n = std::stoi(m.substr(m.find("processes ") + 10));
    for (int r = 0; r < n; ++r) {
      Particles<D> part;
      load_checkpoint(checkpoint_piece(outdir, r, n), s, part, c, at, rows);
      P.append(part);
    }
  } else {
    load_checkpoint(checkpoint_file(outdir), s, P, c, at, rows);
  }
  std::vector<std::pair<Vec<D>, Vec<D>>> r;
  for (std::size_t p = 0; p < P.size(); ++p) r.emplace_back(P.x_ref[p], P.x[p]);
  std::sort(r.begin(), r.end(), [](const auto& a, const auto& b) {
    return std::lexicographical_compare(a.first.begin(), a.first.end(), b.first.begin(), b.first.end());
  });
  return r;
}

template <int D>
void expect_same_points(const ScenarioOf<D>& s, const fs::path& a, const fs::path& b, double tol,
                        const std::string& what) {
  const auto one = final_points(s, a), all = final_points(s, b);
  ASSERT_EQ(one.size(), all.size()) << what;
  ASSERT_GT(one.size(), 0u) << what;
  double extent = 0.0, worst = 0.0, moved = 0.0;
  for (std::size_t i = 0; i < one.size(); ++i) {
    extent = std::max(extent, one[i].second.cwiseAbs().maxCoeff());
    // (x_ref: where the point stood at its stage's start, itself within round-off)
    worst = std::max({worst, (one[i].second - all[i].second).cwiseAbs().maxCoeff(),
                      (one[i].first - all[i].first).cwiseAbs().maxCoeff()});
    moved = std::max(moved, (one[i].second - one[i].first).norm());
  }
  EXPECT_LE(worst, tol * extent) << what << ": the positions differ by up to " << worst << " m";
  EXPECT_GT(moved, 1e-4) << what << ": the points did not move";
}

// A fresh folder every process names alike (made by the first).
fs::path folder(const std::string& name, const Processes& world) {
  const fs::path dir = fs::current_path() / ("mpi_run_" + name);
  if (world.rank() == 0) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  world.barrier();
  return dir;
}

template <int D>
RunResult run(const ScenarioOf<D>& s, const fs::path& outdir, const Processes& procs, long stop_at = -1,
              const fs::path& restart = {}) {
  RunOptions o;
  o.progress = false;
  o.processes = procs;
  o.checkpoint_every = 100000;  // (one at the end: the final points)
  o.stop_at_step = stop_at;
  o.restart = restart;
  return run_simulation(s, outdir, o);
}

// A run of `text` split among the processes against one process's: series, stage measures and
// final points within 1e-12 (the first process compares; the others return false).
bool expect_run_equals_one(const std::string& text, const std::string& name, RunResult& one) {
  const Processes world = Processes::world();
  const Scenario s = parse_scenario(text, name + ".toml");
  const fs::path dir = folder(name, world);
  const RunResult all = run(s, dir / "all", world);
  EXPECT_TRUE(all.completed) << all.message;
  if (world.rank() != 0) return false;
  one = run(s, dir / "one", Processes{});
  EXPECT_TRUE(one.completed) << one.message;
  EXPECT_EQ(all.particles, one.particles);
  EXPECT_EQ(all.steps, one.steps);
  expect_same_series(dir / "one/series.csv", dir / "all/series.csv", 1e-12, name);
  EXPECT_EQ(all.stages.size(), one.stages.size());
  for (std::size_t k = 0; k < std::min(all.stages.size(), one.stages.size()); ++k) {
    const StageMeasures &a = all.stages[k], &b = one.stages[k];
    const double L = 16.0;  // (lengths against the grid's)
    EXPECT_NEAR(a.runout, b.runout, 1e-12 * L) << k;
    EXPECT_NEAR(a.max_displacement, b.max_displacement, 1e-12 * L) << k;
    EXPECT_NEAR(a.height_end, b.height_end, 1e-12 * L) << k;
    EXPECT_NEAR(a.plastic_volume, b.plastic_volume, 1e-12 * L * L) << k;
    EXPECT_EQ(a.plastic_points, b.plastic_points) << k;
    EXPECT_NEAR(a.peak_mean_speed, b.peak_mean_speed, 1e-12 * std::max(1.0, b.peak_mean_speed)) << k;
  }
  expect_same_points(s, dir / "one", dir / "all", 1e-12, name);
  return true;
}

TEST(DistributedRun, SlideEqualsOneProcess) {
  RunResult one;
  if (!expect_run_equals_one(kSlope, "slide", one)) return;
  ASSERT_EQ(one.stages.size(), 2u);
  EXPECT_GT(one.stages[1].plastic_points, 0) << "the slide did not yield";
  EXPECT_GT(one.stages[1].runout, 0.5) << "the slide did not run out";
  const Processes world = Processes::world();
  const fs::path dir = fs::current_path() / "mpi_run_slide";
  // Frames: an index over the processes' pieces, as many points as one process writes.
  const std::string pvd = test::file_text(dir / "all/particles.pvd");
  EXPECT_NE(pvd.find("particles_000000.pvtu"), std::string::npos) << pvd;
  const auto file = pvd.rfind("file=\"") + 6;
  const std::string last = pvd.substr(file, pvd.find(".pvtu", file) - file);  // the last frame
  const std::string index = test::file_text(dir / "all" / (last + ".pvtu"));
  long cells = 0;
  for (int r = 0; r < world.size(); ++r) {
    const std::string piece = fmt::format("{}/piece_{:04}.vtu", last, r);
    EXPECT_NE(index.find("Source=\"" + piece + "\""), std::string::npos) << index;
    const std::string head = test::file_text(dir / "all" / piece).substr(0, 400);
    const auto at = head.find("NumberOfCells=\"");
    ASSERT_NE(at, std::string::npos) << piece;
    cells += std::stol(head.substr(at + 15));
  }
  EXPECT_EQ(cells, one.particles);
  EXPECT_NE(index.find("<PDataArray type=\"Float32\" Name=\"stress\" NumberOfComponents=\"6\""),
            std::string::npos);
  // series.csv and summary.json are written once, by the first process, with the count of all.
  const std::string summary = test::file_text(dir / "all/summary.json");
  EXPECT_NE(summary.find(fmt::format("\"particles\": {},", one.particles)), std::string::npos) << summary;
  EXPECT_NE(summary.find(fmt::format("\"processes\": {{\"count\": {},", world.size())), std::string::npos);
}

// Splitting (Thesis §3.4) in the slide: the same points split, to the same count, and the run's
// cap is shared among the processes.
TEST(DistributedRun, SlideWithSplittingEqualsOneProcess) {
  std::string text = kSlope;
  const std::string shape = "shape = \"polygon\"";
  text.replace(text.find(shape), shape.size(), shape + "\nsplit = true");
  RunResult one;
  if (!expect_run_equals_one(text + "[splitting]\nalpha = 1.3\nbeta = 0.75\ngamma = 0.3\n", "split", one))
    return;
  EXPECT_GT(one.particles, 1500) << "no point split";
}

// The cap binds: its points are the run's, not each process's (where it binds, which points split
// depends on the split).
// Split points land unevenly among the processes: once the most one holds pass rebalance_above
// times the mean, the points are cut into blocks again at once (as every sort_every steps), and the
// run still equals one process's; `rebalances` counts the repartitions that moved points.
TEST(DistributedRun, SplitSharesAreEvenedOut) {
  std::string text = kSlope;
  const std::string shape = "shape = \"polygon\"";
  text.replace(text.find(shape), shape.size(), shape + "\nsplit = true");
  RunResult one;
  if (!expect_run_equals_one(
          text + "[splitting]\nalpha = 1.3\nbeta = 0.75\ngamma = 0.3\nrebalance_above = 1.01\n", "evened",
          one))
    return;
  const std::string summary = test::file_text(fs::current_path() / "mpi_run_evened/all/summary.json");
  const auto at = summary.find("\"rebalances\": ");
  ASSERT_NE(at, std::string::npos) << summary;
  EXPECT_GT(std::stol(summary.substr(at + 15)), 0) << "no point moved between the processes";
  const auto im = summary.find("\"imbalance\": ");
  ASSERT_NE(im, std::string::npos);
  EXPECT_LE(std::stod(summary.substr(im + 13)), 1.01) << summary;
  EXPECT_GT(one.particles, 1500) << "no point split";
  // What a process sent per step: the grid's layers and the moved points, to its neighbour.
  const auto bytes = summary.find("\"bytes_per_step\": "), messages = summary.find("\"messages_per_step\": ");
  ASSERT_NE(bytes, std::string::npos) << summary;
  ASSERT_NE(messages, std::string::npos) << summary;
  EXPECT_GT(std::stod(summary.substr(bytes + 18)), 0.0) << summary;
  EXPECT_GE(std::stod(summary.substr(messages + 21)), 1.0) << summary;
}

TEST(DistributedRun, SplittingCapIsTheRuns) {
  std::string text = kSlope;
  const std::string shape = "shape = \"polygon\"";
  text.replace(text.find(shape), shape.size(), shape + "\nsplit = true");
  text += "[splitting]\nalpha = 1.3\nbeta = 0.75\ngamma = 0.3\nmax_points = 1420\n";
  const Processes world = Processes::world();
  const RunResult all = run(parse_scenario(text, "capped.toml"), folder("capped", world) / "all", world);
  EXPECT_TRUE(all.completed) << all.message;
  EXPECT_GT(all.particles, 1395);
  EXPECT_LE(all.particles, 1420);
}

TEST(DistributedRun, CheckpointInPiecesResumes) {
  const Processes world = Processes::world();
  const Scenario s = parse_scenario(kSlope, "slope.toml");
  const fs::path dir = folder("resume", world);
  const RunResult whole = run(s, dir / "whole", world);
  ASSERT_TRUE(whole.completed) << whole.message;
  const long stop = whole.steps / 2 + 3;  // in the slide
  const RunResult cut = run(s, dir / "cut", world, stop);
  ASSERT_TRUE(cut.interrupted) << cut.message;
  if (world.rank() == 0) {
    EXPECT_TRUE(fs::exists(checkpoint_manifest(dir / "cut")));
    EXPECT_FALSE(fs::exists(checkpoint_file(dir / "cut")));
    fs::copy(dir / "cut", dir / "cut_alone", fs::copy_options::recursive);
  }
  world.barrier();
  // The same count: bit for bit.
  const RunResult resumed = run(s, dir / "cut", world, -1, checkpoint_file(dir / "cut"));
  ASSERT_TRUE(resumed.completed) << resumed.message;
  if (world.rank() != 0) return;
  EXPECT_EQ(test::file_text(dir / "cut/series.csv"), test::file_text(dir / "whole/series.csv"));
  expect_same_points(s, dir / "whole", dir / "cut", 0.0, "resumed on as many processes");
  // Another count (one process reads every piece): within round-off of the run it continues.
  const RunResult alone = run(s, dir / "cut_alone", Processes{}, -1, checkpoint_file(dir / "cut_alone"));
  ASSERT_TRUE(alone.completed) << alone.message;
  expect_same_series(dir / "whole/series.csv", dir / "cut_alone/series.csv", 1e-12, "resumed alone");
  expect_same_points(s, dir / "whole", dir / "cut_alone", 1e-12, "resumed alone");
}

// A one-process checkpoint, whole and as one piece with its manifest (with the pieces' points,
// each process reads the run of them that is its share; without, it keeps its share of every
// piece), resumed on N processes.
TEST(DistributedRun, CheckpointOfOneProcessResumesOnSeveral) {
  const Processes world = Processes::world();
  const Scenario s = parse_scenario(kSlope, "slope.toml");
  const fs::path dir = folder("spread", world);
  if (world.rank() == 0) {  // (no ASSERT before a collective call: the others would wait)
    EXPECT_TRUE(run(s, dir / "whole", Processes{}).completed);
    const RunResult cut = run(s, dir / "cut", Processes{}, 900);  // (in the slide)
    EXPECT_TRUE(cut.interrupted);
    fs::copy(dir / "cut", dir / "piece", fs::copy_options::recursive);
    fs::rename(checkpoint_file(dir / "piece"), checkpoint_piece(dir / "piece", 0, 1));
    std::ofstream(checkpoint_manifest(dir / "piece"))
        << "skred checkpoint in pieces\nprocesses 1\nstep " << cut.steps << '\n';
    // As a manifest names it now, with the piece's points: each process reads only its run.
    fs::copy(dir / "piece", dir / "counted", fs::copy_options::recursive);
    std::ofstream(checkpoint_manifest(dir / "counted")) << "skred checkpoint in pieces\nprocesses 1\nstep "
                                                        << cut.steps << "\npoints " << cut.particles << '\n';
  }
  world.barrier();
  for (const char* name : {"cut", "piece", "counted"}) {
    const RunResult spread = run(s, dir / name, world, -1, checkpoint_file(dir / name));
    ASSERT_TRUE(spread.completed) << name << ": " << spread.message;
    if (world.rank() != 0) continue;
    expect_same_series(dir / "whole/series.csv", dir / name / "series.csv", 1e-12, name);
    expect_same_points(s, dir / "whole", dir / name, 1e-12, name);
  }
}

TEST(DistributedRun, Column3DWithHazardMaps) {
  const Processes world = Processes::world();
  std::ifstream in(std::string(SKRED_SOURCE_DIR) + "/examples/column_3d.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const std::string end = "end_time = 2.0";
  ASSERT_NE(text.find(end), std::string::npos);
  text.replace(text.find(end), end.size(), "end_time = 0.02");
  const Scenario3 s = std::get<Scenario3>(parse_any_scenario(text, "column_3d.toml"));
  const fs::path dir = folder("column3d", world);
  const RunResult all = run(s, dir / "all", world);
  ASSERT_TRUE(all.completed) << all.message;
  if (world.rank() != 0) return;
  const RunResult one = run(s, dir / "one", Processes{});
  ASSERT_TRUE(one.completed) << one.message;
  expect_same_series(dir / "one/series.csv", dir / "all/series.csv", 1e-12, "3D column");
  expect_same_points(s, dir / "one", dir / "all", 1e-12, "3D column");
  for (const char* map : {"max_speed", "max_displacement", "deposit_thickness", "terrain"}) {
    std::stringstream a(test::file_text(dir / "one/maps" / (std::string(map) + ".asc"))),
        b(test::file_text(dir / "all/maps" / (std::string(map) + ".asc")));
    std::vector<double> va, vb;  // (the header's words are skipped)
    for (std::string w; a >> w;)
      if (w.find_first_not_of("0123456789.-+eE") == std::string::npos) va.push_back(std::stod(w));
    for (std::string w; b >> w;)
      if (w.find_first_not_of("0123456789.-+eE") == std::string::npos) vb.push_back(std::stod(w));
    ASSERT_EQ(va.size(), vb.size()) << map;
    EXPECT_GT(va.size(), 100u) << map;
    double scale = 0.0, worst = 0.0;
    for (std::size_t i = 0; i < va.size(); ++i) {
      scale = std::max(scale, std::abs(va[i]));
      worst = std::max(worst, std::abs(va[i] - vb[i]));
    }
    EXPECT_LE(worst, 1e-6 * scale) << map << " (written with 7 digits)";
  }
}

// An implicit run split against one process's, within the solver's tolerance (the first
// process compares and returns true).
bool expect_implicit_run_equals_one(const Scenario& s, const std::string& name) {
  const Processes world = Processes::world();
  const fs::path dir = folder(name, world);
  const RunResult all = run(s, dir / "all", world);
  EXPECT_TRUE(all.completed) << all.message;
  if (world.rank() != 0 || !all.completed) return false;
  const RunResult one = run(s, dir / "one", Processes{});
  EXPECT_TRUE(one.completed) << one.message;
  EXPECT_EQ(all.steps, one.steps);
  expect_same_series(dir / "one/series.csv", dir / "all/series.csv", 1e-8, name);
  expect_same_points(s, dir / "one", dir / "all", 1e-8, name);
  const std::string summary = test::file_text(dir / "all/summary.json");
  EXPECT_NE(summary.find(fmt::format("parallel over {} processes", world.size())), std::string::npos)
      << name << ": not PETSc's parallel matrix: " << summary;
  return true;
}

// The implicit integrator's run (R6, examples/hollow_cylinder.toml: quasi-static, a pressure
// that follows the inner face).
TEST(DistributedRun, ImplicitCylinderEqualsOneProcess) {
  const std::string path = std::string(SKRED_SOURCE_DIR) + "/examples/hollow_cylinder.toml";
  expect_implicit_run_equals_one(std::get<Scenario>(load_any_scenario(path)), "cylinder");
}

// The implicit R6 cylinder (quasi-static, four load steps) interrupted after two at N processes
// and resumed: at N bit for bit, alone within the solver's tolerance (the solvers' sums run over
// other rows). With MUMPS (direct) and with CG and GAMG (iterative): each new pattern gets a
// fresh solver, so the resumed run's first one is the whole run's (a reset GAMG kept some of its
// set-up, and the resumed steps differed by 1e-13 m). Beyond 2 processes GAMG's set-up is not
// always the same from run to run (measured at 4: three runs, three series, apart by 1e-15
// relative; at 3, one test in six), so there the iterative runs are compared within the
// solver's tolerance.
TEST(DistributedRun, ImplicitCheckpointInPiecesResumes) {
  const Processes world = Processes::world();
  for (const std::string solver : {"direct", "iterative"}) {
    std::string text = test::file_text(std::string(SKRED_SOURCE_DIR) + "/examples/hollow_cylinder.toml");
    const std::string key = "load_steps = 4";
    ASSERT_NE(text.find(key), std::string::npos);
    text.replace(text.find(key), key.size(), key + "\nlinear_solver = \"" + solver + "\"");
    const Scenario s = parse_scenario(text, "hollow_cylinder.toml");
    const fs::path dir = folder("implicit_resume_" + solver, world);
    const RunResult whole = run(s, dir / "whole", world);
    ASSERT_TRUE(whole.completed) << whole.message;
    ASSERT_EQ(whole.steps, 4);
    const RunResult cut = run(s, dir / "cut", world, 2);
    ASSERT_TRUE(cut.interrupted) << cut.message;
    if (world.rank() == 0) fs::copy(dir / "cut", dir / "cut_alone", fs::copy_options::recursive);
    world.barrier();
    const RunResult resumed = run(s, dir / "cut", world, -1, checkpoint_file(dir / "cut"));
    ASSERT_TRUE(resumed.completed) << resumed.message;
    if (world.rank() != 0) continue;
    if (solver == "direct" || world.size() <= 2) {
      EXPECT_EQ(test::file_text(dir / "cut/series.csv"), test::file_text(dir / "whole/series.csv")) << solver;
      expect_same_points(s, dir / "whole", dir / "cut", 0.0, solver + ", resumed on as many processes");
    } else {
      expect_same_series(dir / "whole/series.csv", dir / "cut/series.csv", 1e-8, solver + ", resumed");
      expect_same_points(s, dir / "whole", dir / "cut", 1e-8, solver + ", resumed on as many processes");
    }
    const RunResult alone = run(s, dir / "cut_alone", Processes{}, -1, checkpoint_file(dir / "cut_alone"));
    ASSERT_TRUE(alone.completed) << alone.message;
    expect_same_series(dir / "whole/series.csv", dir / "cut_alone/series.csv", 1e-8,
                       solver + ", resumed alone");
    expect_same_points(s, dir / "whole", dir / "cut_alone", 1e-8, solver + ", resumed alone");
  }
}

// The R6 cylinder's `skred run` with Acosta's DM-GC (examples/hollow_cylinder.toml, GIMP,
// Acosta's load stepping: the DM-G stiffness cell by cell, CMPM's recovery).
TEST(DistributedRun, ImplicitRemediesEqualOneProcess) {
  const std::string path = std::string(SKRED_SOURCE_DIR) + "/examples/hollow_cylinder.toml";
  std::string text = test::file_text(path);
  const std::string key = "[implicit]\n";
  ASSERT_NE(text.find(key), std::string::npos);
  text.replace(text.find(key), key.size(),
               key + "integration = \"double-mapping-gimp\"\nstress_recovery = \"cmpm\"\n");
  expect_implicit_run_equals_one(parse_scenario(text, path), "remedies");
}

}  // namespace
}  // namespace skred
