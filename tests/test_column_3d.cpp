// The scenario pipeline in 3D (issue "The engine opened up": dimension end to end):
//  - the Mohr-Coulomb column of `skred bench --problem column` (phi = 30, c = 0.5 kPa,
//    K0 = nu/(1 - nu) initial stress, Thesis eq. 5.6-5.7) as a slab two cells thick between
//    roller z walls must reproduce the 2D plane-strain run of the same column (runout, front
//    travel and final height within 2 %, gravity work per metre of thickness within 2 %), and
//    no point of it may move or be moving along z at the end (to round-off);
//  - a square column collapsing in both horizontal directions spreads symmetrically: runout
//    along x and z (and towards - and +) and the deposit's extents agree to one cell, and no
//    mass is lost;
//  - one survey, a 2D and a 3D study (issue 58): that soil under a ground surface from an .asc
//    raster of a plane-strain section extruded across z, as the slab, reproduces the 2D run of
//    the section through the same raster (runout and gravity work within 2 %), and `skred check`
//    of the 3D slope gives Bishop's factor of its steepest 2D section, the 2D check's.
// Coarse grids (h = 0.25 m, 2 points per cell and axis) keep each run to a few seconds.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gdal_test_util.hpp"
#include "io_test_util.hpp"
#include "run/checkpointing.hpp"
#include "run/simulation.hpp"
#include "run/slide_measures.hpp"
#include "run/slope_stability.hpp"
#include "scenario/build.hpp"
#include "scenario/initial_stress.hpp"
#include "solver/explicit_solver.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace skred;

namespace {

constexpr double kCell = 0.25;

// The bench's Mohr-Coulomb column, 1.5 m wide and 3 m high against the x_min wall: in 2D, or
// (three_d) as a slab between z = 0 and z = 2 cells with roller z walls.
std::string column_text(bool three_d) {
  const std::string z = three_d ? ", 0.5" : "", zg = three_d ? ", 0.0" : "";
  return fmt::format(R"(
[grid]
size = [7.5, 3.5{0}]
cell_size = {2}
[[material]]
name = "soil"
model = "mohr-coulomb"
density = 1800.0
young = 10e6
poisson = 0.3
friction = 30.0
cohesion = 500.0
[[body]]
material = "soil"
particles_per_cell = 2
shape = "{3}"
min = [0.0, 0.0{1}]
max = [1.5, 3.0{0}]
[initial_stress]
k0 = "poisson"
[gravity]
acceleration = [0.0, -9.81{1}]
[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"
{4}
[solver]
scheme = "usf"
cfl = 0.4
end_time = 2.5
[output]
interval = 2.5
)",
                     z, zg, kCell, three_d ? "box" : "rectangle",
                     three_d ? "z_min = \"roller\"\nz_max = \"roller\"" : "");
}

// Runs the scenario; with `end`, the points as the run left them (from the checkpoint that a
// run with checkpoints writes at its end).
template <int D>
RunResult run(const ScenarioOf<D>& s, const std::string& name, Particles<D>* end = nullptr) {
  const fs::path out = skred::test::fresh_temp_dir(name);
  RunOptions opt;
  opt.progress = false;
  opt.threads = 2;
  if (end) opt.checkpoint_every = 1L << 40;  // none on the way, one at the end
  RunResult r = run_simulation(s, out, opt);
  EXPECT_TRUE(fs::exists(out / "particles_000001.vtu"));
  EXPECT_TRUE(fs::exists(out / "grid_000001.vtr"));
  if (end && r.completed) {
    SolverClock clock;
    RunProgress<D> at;
    std::vector<SeriesRow> series;
    load_checkpoint(checkpoint_file(out), s, *end, clock, at, series);
    EXPECT_EQ(clock.steps, r.steps);  // the run's last state
  }
  fs::remove_all(out);
  return r;
}

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

// A slope of that soil: a crest 3 m high to x = 0.5 m, a face falling at 1.5 to the floor at
// x = 2.5 m (no point, at odd multiples of 1/16 m, lies on it). Its raster: 16 columns of 0.5 m
// cells over x = 0..7.5 m (centres at easting 1000 + x), 2 rows at northing 5000 (upper) and
// 4999.5, the face's corners on cell centres, so that bilinear sampling is the section exactly.
// The scenarios: the column's with a layer under that surface, in 2D along the section at
// northing 4999.75, in 3D from the raster whole (the slab: z = 5000 - northing from 0 to 0.5 m).
// Returns the 2D and the 3D file.
// The raster slope's height at x along its fall line (a 56 degree face between two flats).
double raster_slope_at(double x) { return x <= 0.5 ? 3.0 : x >= 2.5 ? 0.0 : 3.0 - 1.5 * (x - 0.5); }

std::pair<fs::path, fs::path> write_raster_slope(const fs::path& dir) {
  test::write_asc(dir / "surface.asc", 16, 2, 999.75, 4999.25, 0.5,
                  [](int c, int) { return raster_slope_at(0.5 * c); });
  for (const bool three_d : {false, true}) {
    std::string t = column_text(three_d);
    const std::size_t shape = t.find("shape = "), end = t.find("[initial_stress]");
    t.replace(
        shape, end - shape,
        fmt::format("shape = \"layer\"\n[ground]\nsurface = \"surface.asc\"\n{}\n",
                    three_d ? "origin = [1000, 5000]" : "section = [[1000, 4999.75], [1007.5, 4999.75]]"));
    std::ofstream(dir / (three_d ? "slab.toml" : "plane.toml")) << t;
  }
  return {dir / "plane.toml", dir / "slab.toml"};
}

}  // namespace

TEST(Column3D, SlabWithRollerSidesReproducesThePlaneStrainRun) {
  const AnyScenario any2 = parse_any_scenario(column_text(false), "plane.toml");
  const AnyScenario any3 = parse_any_scenario(column_text(true), "slab.toml");
  ASSERT_TRUE(std::holds_alternative<Scenario>(any2));
  ASSERT_TRUE(std::holds_alternative<Scenario3>(any3));
  const Scenario3& s3 = std::get<Scenario3>(any3);
  EXPECT_EQ(s3.cell_count(), 30L * 14 * 2);
  const RunResult r2 = run(std::get<Scenario>(any2), "plane");
  Particles<3> end;
  const RunResult r3 = run(s3, "slab", &end);
  ASSERT_TRUE(r2.completed) << r2.message;
  ASSERT_TRUE(r3.completed) << r3.message;
  EXPECT_EQ(r3.particles, 4 * r2.particles);  // two cells of 2 points each along z
  const StageMeasures &m2 = r2.stages.back(), &m3 = r3.stages.back();
  const double thickness = 2 * kCell;
  std::printf(
      "slab vs plane strain: runout %.4g vs %.4g m (z: %.4g, %.4g), front travel %.5g vs "
      "%.5g m (%.3f %%), final height %.5g vs %.5g m (%.3f %%), gravity work per metre "
      "%.6g vs %.6g J/m (%.3f %%)\n",
      m3.runout, m2.runout, m3.runout_z_min, m3.runout_z_max, m3.max_displacement, m2.max_displacement,
      100 * rel(m3.max_displacement, m2.max_displacement), m3.height_end, m2.height_end,
      100 * rel(m3.height_end, m2.height_end), m3.gravity_work / thickness, m2.gravity_work,
      100 * rel(m3.gravity_work / thickness, m2.gravity_work));
  EXPECT_GT(m2.runout, 4 * kCell);  // the column did collapse
  EXPECT_LT(m2.height_end, 0.8 * m2.height_start);
  EXPECT_LE(rel(m3.runout, m2.runout), 0.02);
  EXPECT_LE(rel(m3.max_displacement, m2.max_displacement), 0.02);
  EXPECT_LE(rel(m3.height_end, m2.height_end), 0.02);
  EXPECT_LE(rel(m3.gravity_work / thickness, m2.gravity_work), 0.02);
  // Nothing moves across the slab. The roller z walls hold the nodes on z = 0 and 0.5 m, and the
  // slab is its own mirror image about z = 0.25 m, so the middle nodes get no z force either: every
  // point must end where it started in z (its lattice position, (k + 1/2) h/2), at rest in z, to
  // round-off (measured: |u_z| = 0, |v_z| <= 1.1e-16 m/s). The runout along z, asserted 0 before,
  // cannot tell: the slab fills the grid between its z walls (with z_max = "fixed" it stays 0
  // while points move 3.7 cm along z and these bounds fail).
  ASSERT_EQ(end.size(), static_cast<std::size_t>(r3.particles));
  const double height = 3.0, speed = std::sqrt(9.81 * height);  // the problem's length and speed
  double dz = 0.0, vz = 0.0, off_lattice = 0.0, fzz = 0.0;
  for (std::size_t p = 0; p < end.size(); ++p) {
    dz = std::max(dz, std::abs(end.x[p][2] - end.x_ref[p][2]));
    vz = std::max(vz, std::abs(end.v[p][2]));
    const double q = kCell / 2, k = std::floor(end.x_ref[p][2] / q);
    off_lattice = std::max(off_lattice, std::abs(end.x_ref[p][2] - (k + 0.5) * q));
    fzz = std::max(fzz, std::abs(end.F[p](2, 2) - 1.0));
  }
  std::printf("slab at the end: max |u_z| %.2e m, max |v_z| %.2e m/s, max |F_zz - 1| %.3g\n", dz, vz, fzz);
  EXPECT_LE(off_lattice, 1e-12);
  EXPECT_LE(dz, 1e-9 * height);
  EXPECT_LE(vz, 1e-9 * speed);
  // Not asserted: F_zz - 1 is not zero, up to 0.062 (measured). The cell-averaged volumetric
  // strain (the slide default; volumetric_averaging.hpp) adds (div_c - div_p) / d to the diagonal
  // of each point's velocity gradient, d = 3 here: the z axis takes a third of the correction
  // although the grid (v_z = 0) does not strain the slab along z, while the 2D run adds a half to
  // xx and yy and nothing to zz. With volumetric_strain = "point" F_zz stays exactly 1 and the
  // slab meets the plane-strain run more closely (front travel within 0.03 %, not 0.3 %).
}

TEST(Column3D, SquareColumnSpreadsSymmetricallyInXAndZ) {
  // A 1 m x 1.5 m x 1 m column in the middle of a 5 m x 5 m floor (fixed base), free to
  // spread towards -x, +x, -z and +z.
  const Scenario3 s = std::get<Scenario3>(parse_any_scenario(fmt::format(R"(
[grid]
size = [5.0, 2.0, 5.0]
cell_size = {}
[[material]]
name = "soil"
model = "mohr-coulomb"
density = 1800.0
young = 10e6
poisson = 0.3
friction = 30.0
cohesion = 500.0
[[body]]
material = "soil"
shape = "box"
min = [2.0, 0.0, 2.0]
max = [3.0, 1.5, 3.0]
[initial_stress]
k0 = "poisson"
[gravity]
acceleration = [0.0, -9.81, 0.0]
[boundary]
y_min = "fixed"
[solver]
scheme = "usf"
cfl = 0.4
end_time = 1.5
velocity_transfer = "flip"
volumetric_strain = "point"
)",
                                                                         kCell),
                                                             "square.toml"));
  Particles<3> P = build_particles(s);
  ASSERT_EQ(P.size(), 4u * 6 * 4 * 8);
  apply_initial_stress(s, P);
  ExplicitSolver<3> solver(scenario_grid(s), P, stage_materials(s, s.stages[0]), solver_settings(s), 2);
  const double mass0 = solver.totals().mass;
  EXPECT_NEAR(mass0, 1800.0 * 1.5, 1e-9 * mass0);
  const double L = s.cells[0] * kCell;
  StageTracker<3> tracker("collapse", P, 0.0, 0.0, 0.0, 0.0, 0.0, kCell, L, 0.0, 0.0, L);
  while (solver.time() < s.end_time - 0.5 * solver.dt()) ASSERT_TRUE(solver.step().ok);
  const auto t = solver.totals();
  const StageMeasures m =
      tracker.finish(P, solver.time(), solver.steps(), t.kinetic_energy, 0, 0, 0, "duration");
  const MaterialExtent e = material_extent(P);
  std::printf(
      "square column: runout -x %.4g +x %.4g -z %.4g +z %.4g m; deposit x [%.4f, %.4f], "
      "z [%.4f, %.4f], height %.4g m (from 1.5); mass change %.2e, momentum (%.2e, %.2e, %.2e)\n",
      m.runout_x_min, m.runout_x_max, m.runout_z_min, m.runout_z_max, e.x_min, e.x_max, e.z_min, e.z_max,
      m.height_end, t.mass - mass0, t.momentum[0], t.momentum[1], t.momentum[2]);
  EXPECT_EQ(t.mass, mass0);  // mass conservation: point masses never change
  EXPECT_GE(std::min({m.runout_x_min, m.runout_x_max, m.runout_z_min, m.runout_z_max}), 2 * kCell);
  EXPECT_LT(m.height_end, 0.8 * 1.5);
  const double tol = kCell + 1e-9;  // symmetric within one cell
  EXPECT_LE(std::abs(m.runout_x_max - m.runout_z_max), tol);
  EXPECT_LE(std::abs(m.runout_x_min - m.runout_z_min), tol);
  EXPECT_LE(std::abs(m.runout_x_min - m.runout_x_max), tol);
  EXPECT_LE(std::abs(m.runout_z_min - m.runout_z_max), tol);
  const double reach[4] = {2.5 - e.x_min, e.x_max - 2.5, 2.5 - e.z_min, e.z_max - 2.5};
  for (double r : reach) EXPECT_LE(std::abs(r - reach[0]), tol);
  EXPECT_LT(std::abs(t.momentum[0]) + std::abs(t.momentum[2]), 1e-6 * mass0);
}

TEST(Column3D, RasterSlopeWithRollerSidesReproducesThe2DRunOfItsSection) {
  const skred::test::TempDir dir;
  const auto [plane, slab] = write_raster_slope(dir.path());
  const Scenario s2 = std::get<Scenario>(load_any_scenario(plane.string()));
  const Scenario3 s3 = std::get<Scenario3>(load_any_scenario(slab.string()));
  const RunResult r2 = run(s2, "plane"), r3 = run(s3, "slab");
  ASSERT_TRUE(r2.completed) << r2.message;
  ASSERT_TRUE(r3.completed) << r3.message;
  EXPECT_EQ(r3.particles, 4 * r2.particles);  // two cells of 2 points each along z
  const StageMeasures &m2 = r2.stages.back(), &m3 = r3.stages.back();
  const double thickness = 2 * kCell;
  std::printf(
      "raster slab vs its 2D section: runout %.4g vs %.4g m (%.3f %%), gravity work per metre %.6g vs "
      "%.6g J/m (%.3f %%)\n",
      m3.runout, m2.runout, 100 * rel(m3.runout, m2.runout), m3.gravity_work / thickness, m2.gravity_work,
      100 * rel(m3.gravity_work / thickness, m2.gravity_work));
  EXPECT_GT(m2.runout, 4 * kCell);  // the slope did fail
  EXPECT_LE(rel(m3.runout, m2.runout), 0.02);
  EXPECT_LE(rel(m3.gravity_work / thickness, m2.gravity_work), 0.02);
}

TEST(Column3D, RasterSlopeCheckGivesBishopsFactorOfItsSteepestSectionAsThe2DCheck) {
  const skred::test::TempDir dir;
  const auto [plane, slab] = write_raster_slope(dir.path());
  const SlopeStability le2 = slope_stability(std::get<Scenario>(load_any_scenario(plane.string())));
  const SlopeStability le3 = slope_stability(std::get<Scenario3>(load_any_scenario(slab.string())));
  ASSERT_TRUE(le2.computed) << le2.why_not;
  ASSERT_TRUE(le3.computed) << le3.why_not;
  EXPECT_LT(le2.critical.factor, 1.0);  // a 56 degree face of c = 0.5 kPa, phi = 30 does not stand
  EXPECT_DOUBLE_EQ(le3.critical.factor, le2.critical.factor);
  EXPECT_DOUBLE_EQ(le3.critical.circle.radius, le2.critical.circle.radius);
  // Both rows of cells across z are the section; the first is taken.
  const auto [status, out] =
      iotest::run_command(iotest::shell_quote(SKRED_BINARY) + " check " + iotest::shell_quote(slab.string()));
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(
      out.find("in stage 'run', on the 2D section of the cells z = 0 to 0.25 m along x, the steepest (mean "
               "slope"),
      std::string::npos)
      << out;
  EXPECT_NE(out.find(fmt::format("as plane strain): F = {:.3f} on the circle", le2.critical.factor)),
            std::string::npos)
      << out;
}

// The same slope falling along z (the raster's fall line along easting, +x to the north at
// rotation 90 so that z runs east): the check takes the steepest column of cells along z, with
// the 2D section's factor and circle.
TEST(Column3D, RasterSlopeFallingAlongZIsCheckedOnItsSectionAlongZ) {
  const skred::test::TempDir dir;
  const auto [plane, slab] = write_raster_slope(dir.path());
  test::write_asc(dir.path() / "surface_z.asc", 16, 4, 999.75, 4999.25, 0.5,
                  [](int c, int) { return raster_slope_at(0.5 * c); });
  std::string t = iotest::read_text(slab);
  const auto replace = [&](const std::string& a, const std::string& b) {
    const std::size_t at = t.find(a);
    ASSERT_NE(at, std::string::npos) << a;
    t.replace(at, a.size(), b);
  };
  replace("size = [7.5, 3.5, 0.5]", "size = [0.5, 3.5, 7.5]");
  replace("surface = \"surface.asc\"", "surface = \"surface_z.asc\"");
  replace("origin = [1000, 5000]", "origin = [1000, 5000]\nrotation = 90.0");
  std::ofstream(dir.path() / "slab_z.toml") << t;
  const SlopeStability le2 = slope_stability(std::get<Scenario>(load_any_scenario(plane.string())));
  const SlopeStability le3 =
      slope_stability(std::get<Scenario3>(load_any_scenario((dir.path() / "slab_z.toml").string())));
  ASSERT_TRUE(le3.computed) << le3.why_not;
  EXPECT_EQ(le3.axis, 'z');
  EXPECT_DOUBLE_EQ(le3.critical.factor, le2.critical.factor);
  EXPECT_DOUBLE_EQ(le3.critical.circle.radius, le2.critical.circle.radius);
  EXPECT_NE(le3.section.find("of the cells x = 0 to 0.25 m along z"), std::string::npos) << le3.section;
  EXPECT_NE(slope_stability_line(le3).find(
                fmt::format("sliding towards {}z", le2.critical.direction > 0 ? "+" : "-")),
            std::string::npos);
}
