// The implicit integrator (src/implicit; González Acosta et al. 2020) against answers from
// outside the code: the oedometric column under its own weight (R2), the hollow cylinder under
// internal pressure in axisymmetric geometry (R6, Acosta App. A2), the vibrating bar with
// Newmark's rule (R1), the momentum of colliding discs (R3, Acosta eq. 54), Newton's quadratic
// convergence with the consistent tangent, and the run driver's hand-over between integrators.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "implicit/implicit_solver.hpp"
#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "scenario/initial_stress.hpp"
#include "scenario/scenario.hpp"
#include "support.hpp"
#include "temp_dir.hpp"

using namespace skred;

namespace {

// A scenario's points and its first stage's implicit integrator, ready to step.
struct ImplicitRun {
  Scenario s;
  Particles<2> P;
  ImplicitSolver<2> solver;
  explicit ImplicitRun(const std::string& text, int threads = 2)
      : s(parse_scenario(text, "implicit.toml")),
        P(build_particles(s)),
        solver(implicit_model(s), P, stage_materials(s, s.stages.front()), threads) {
    const Stage& st = s.stages.front();
    solver.set_stage(st.implicit, stage_time_step(s, st), st.duration);
    solver.begin_stage(stage_materials(s, st), st.gravity_ramp_time);
  }
  // Steps to the stage's end; false (with the status in `failed`) when a step fails.
  bool run() {
    while (solver.time() < s.stages.front().duration - 1e-9 * solver.dt()) {
      failed = solver.step();
      if (!failed.ok) return false;
    }
    return true;
  }
  StepStatus failed;
};

std::string column_text(const std::string& solver) { return test::r2_column_text(solver); }

constexpr double kRho = 1800.0, kG = 9.81, kH = 0.1, kM = 1e6;

// RMS over the points of (sigma_yy + rho g d) / (rho g H), d the depth of the point's reference
// position below the top.
double overburden_error(const Particles<2>& P) {
  double e = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double d = kH - P.x_ref[p][1];
    const double r = (P.stress[p][1] + kRho * kG * d) / (kRho * kG * kH);
    e += r * r;
  }
  return std::sqrt(e / static_cast<double>(P.size()));
}

}  // namespace

// R2: a linear problem in one load step takes one Newton iteration; the top settles by
// rho g H^2 / (2M) within 1 %, and sigma_yy at the points is as far from -rho g d as the
// explicit engine's own answer at rest on the same grid (locally damped, 0.2 s).
TEST(ImplicitColumn, OneLoadStepOneIterationMatchesTheOedometer) {
  ImplicitRun run(column_text("[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n"));
  ASSERT_TRUE(run.run()) << run.failed.reason;
  EXPECT_EQ(run.solver.steps(), 1);
  EXPECT_EQ(run.solver.last_step().iterations, 1);
  EXPECT_LT(run.solver.last_step().residual, 1e-10);
  double top = 0.0;
  for (std::size_t p = 0; p < run.P.size(); ++p) top = std::max(top, run.P.x_ref[p][1] - run.P.x[p][1]);
  const double exact = kRho * kG * kH * kH / (2.0 * kM);
  EXPECT_NEAR(top, exact, 0.01 * exact);
  const double implicit_error = overburden_error(run.P);

  Scenario s = parse_scenario(column_text("[solver]\nend_time = 0.2\n"), "explicit.toml");
  Particles<2> P = build_particles(s);
  ExplicitSolver<2> ex(scenario_grid(s), P, stage_materials(s, s.stages.front()), solver_settings(s), 2);
  ex.set_local_damping(0.5);
  P.x_ref = P.x;
  while (ex.time() < 0.2) ASSERT_TRUE(ex.step().ok);
  EXPECT_LT(ex.totals().kinetic_energy, 1e-8 * ex.energy().gravity_work);  // at rest
  const double explicit_error = overburden_error(P);
  // In one load step GIMP with 2 x 2 points per cell gives each cell the exact stress of its
  // middle, so the RMS error is h / (4H) (0.0125) to round-off. The explicit engine at rest is
  // 2 % closer (0.01224): its points have settled by 2 % of a cell, which slants the stress
  // within each cell; more load steps would do the same here. The two agree within 3 %.
  EXPECT_NEAR(implicit_error, 0.005 / (4.0 * kH), 1e-9);
  EXPECT_NEAR(implicit_error, explicit_error, 0.03 * explicit_error)
      << "implicit " << implicit_error << ", explicit " << explicit_error;
  // The stored energy of a linear static answer is half the work of its load (Clapeyron).
  EXPECT_NEAR(run.solver.energy().strain_energy, 0.5 * run.solver.energy().gravity_work,
              1e-9 * run.solver.energy().gravity_work);
}

namespace {

// R6 (Acosta §3.1, App. A2): r_i = 0.5, r_e = 1.5 fixed, E = 1000 kPa, nu = 0.3, no axial
// strain (rollers above and below), pressure p on the inner wall; `material` and `implicit`
// replace the elastic material's model line and add [implicit] keys.
std::string cylinder_text(double h, double p, const std::string& material = "model = \"linear-elastic\"",
                          const std::string& implicit = "") {
  std::ostringstream t;
  t << "[grid]\norigin = [0, 0]\nsize = [1.5, " << 8 * h << "]\ncell_size = " << h
    << "\ngeometry = \"axisymmetric\"\n"
    << "[[material]]\nname = \"m\"\n"
    << material << "\ndensity = 1000.0\nyoung = 1e6\npoisson = 0.3\n"
    << "[[body]]\nname = \"cylinder\"\nmaterial = \"m\"\nshape = \"rectangle\"\nmin = [0.5, 0.0]\nmax = "
       "[1.5, "
    << 8 * h << "]\n"
    << "[[pressure]]\nbody = \"cylinder\"\nside = \"x_min\"\nvalue = " << p << "\nramp_time = 1.0\n"
    << "[boundary]\nx_max = \"fixed\"\ny_min = \"roller\"\ny_max = \"roller\"\n"
    << "[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n[implicit]\n"
    << implicit;
  return t.str();
}

struct Lame {  // Acosta eq. 34-36 in the form u = A1 (r - r_e^2 / r)
  double A1, lambda, G;
  Lame(double p) {
    const double E = 1e6, nu = 0.3;
    lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    G = E / (2 * (1 + nu));
    A1 = 1.0;
    A1 = -p / stresses(0.5)[0];
  }
  std::array<double, 4> stresses(double r) const {  // sigma_r, sigma_y, sigma_theta, u
    const double re2 = 1.5 * 1.5, er = A1 * (1 + re2 / (r * r)), et = A1 * (1 - re2 / (r * r));
    return {lambda * (er + et) + 2 * G * er, lambda * (er + et), lambda * (er + et) + 2 * G * et,
            A1 * (r - re2 / r)};
  }
};

}  // namespace

// R6 at 10 kPa (small strain): sigma_r, sigma_theta and sigma_y at the points within 1 % of p of
// eq. 34-36 outside the cells next to the walls, and u(r) within 1 % of its largest value.
TEST(ImplicitCylinder, AxisymmetricStressesAndDisplacementsMatchLame) {
  const double h = 0.00625, p = 1e4;
  ImplicitRun run(cylinder_text(h, p));
  ASSERT_TRUE(run.run()) << run.failed.reason;
  const Lame exact(p);
  const double u_max = std::abs(exact.stresses(0.5)[3]);
  double worst = 0.0, worst_u = 0.0;
  for (std::size_t q = 0; q < run.P.size(); ++q) {
    const double r = run.P.x_ref[q][0];
    const auto e = exact.stresses(r);
    worst_u = std::max(worst_u, std::abs(run.P.x[q][0] - r - e[3]) / u_max);
    if (r < 0.5 + h || r > 1.5 - h) continue;
    for (int c : {0, 1, 2})
      worst = std::max(worst, std::abs(run.P.stress[q][c] - e[static_cast<std::size_t>(c)]) / p);
  }
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(worst_u, 0.01);
  // Axisymmetric bookkeeping: the hoop stretch is r / r_0, the volume per radian follows it.
  for (std::size_t q = 0; q < run.P.size(); q += 97)
    EXPECT_NEAR(run.P.hoop[q], run.P.x[q][0] / run.P.x_ref[q][0], 1e-12);
}

// Newton's method with the consistent tangent converges quadratically: Tresca (s_u = 6 kPa)
// yields around the inner wall of the cylinder at 10 kPa; the relative residuals of the
// plastic steps fall as r_{k+1} <= 10 r_k^2 until round-off. Acosta's iteration (the elastic
// matrix) reaches the same answer with more iterations.
TEST(ImplicitNewton, ConsistentTangentConvergesQuadratically) {
  const std::string tresca = "model = \"tresca\"\ncohesion = 6e3";
  ImplicitRun newton(cylinder_text(0.0125, 1e4, tresca, "load_steps = 5\n"));
  ImplicitRun elastic(
      cylinder_text(0.0125, 1e4, tresca, "load_steps = 5\niteration = \"elastic\"\nmax_iterations = 200\n"));
  int newton_iterations = 0, elastic_iterations = 0, checked = 0;
  for (int k = 0; k < 5; ++k) {
    ASSERT_TRUE(newton.solver.step().ok);
    ASSERT_TRUE(elastic.solver.step().ok);
    newton_iterations += newton.solver.last_step().iterations;
    elastic_iterations += elastic.solver.last_step().iterations;
    const std::vector<double>& r = newton.solver.residual_history();
    for (std::size_t i = 1; i + 1 < r.size(); ++i)
      if (r[i] > 1e-11) {
        EXPECT_LE(r[i + 1], 10.0 * r[i] * r[i]) << "step " << k << " iteration " << i;
        ++checked;
      }
  }
  EXPECT_GT(checked, 0);  // some step iterated in the plastic range
  long yielding = 0;
  for (const PointState& st : newton.P.state) yielding += st.yielding;
  EXPECT_GT(yielding, 0);
  EXPECT_LT(newton_iterations, elastic_iterations);
  double diff = 0.0;
  for (std::size_t q = 0; q < newton.P.size(); ++q)
    diff = std::max(diff, (newton.P.stress[q] - elastic.P.stress[q]).cwiseAbs().maxCoeff());
  EXPECT_LT(diff, 1e-4 * 1e4);
}

namespace {

// R1's bar (L = 25, E = 100, rho = 1, nu = 0, c = 10; first mode, v0 = 0.1) as a strip one cell
// of 0.5 m high between rollers, dynamic implicit to `end` seconds; `extra` is appended.
std::string bar_text(double end, const std::string& extra) {
  return R"(
[grid]
size = [33.0, 0.5]
cell_size = 0.5
[[material]]
name = "bar"
model = "linear-elastic"
density = 1.0
young = 100.0
poisson = 0.0
[[body]]
name = "bar"
material = "bar"
shape = "rectangle"
min = [0.0, 0.0]
max = [25.0, 0.5]
velocity_sine = { amplitude = [0.1, 0.0], wavelength = 100.0, axis = "x" }
[boundary]
x_min = "fixed"
y_min = "roller"
y_max = "roller"
[solver]
integrator = "implicit"
end_time = )" +
         std::to_string(end) + "\n[implicit]\nanalysis = \"dynamic\"\n" + extra;
}

}  // namespace

// R1: the vibrating bar (L = 25, c = 10, first mode, period 10) with Newmark's trapezoidal rule
// at 10 times the explicit stable step: the period of the centre-of-mass velocity within 2 % and
// the total energy within 0.1 % of its start over 5 periods.
TEST(ImplicitBar, NewmarkKeepsThePeriodAndTheEnergy) {
  ImplicitRun run(bar_text(50.0, ""));
  EXPECT_NEAR(run.solver.dt(), 10.0 * 0.5 / 10.1, 1e-12);  // 10 x h / (c + v0)
  std::vector<double> t, v;
  const double e0 = run.solver.totals().kinetic_energy;
  double drift = 0.0;
  while (run.solver.time() < 50.0 - 1e-9) {
    ASSERT_TRUE(run.solver.step().ok);
    const ParticleTotals<2> tot = run.solver.totals();
    t.push_back(run.solver.time());
    v.push_back(tot.momentum[0] / tot.mass);
    drift = std::max(drift, std::abs(tot.kinetic_energy + run.solver.energy().strain_energy - e0) / e0);
  }
  const std::vector<double> z = test::zero_crossings(t, v);
  ASSERT_GE(z.size(), 5u);
  const double period = (z.back() - z.front()) / static_cast<double>(z.size() - 1);
  EXPECT_NEAR(period, 10.0, 0.2);
  EXPECT_LT(drift, 1e-3);
}

// Acosta eq. 54: the momentum of an isolated system is conserved to round-off (R3's discs,
// dynamic implicit, through their collision).
TEST(ImplicitDiscs, MomentumIsConservedToRoundOff) {
  std::ostringstream t;
  t << "[grid]\nsize = [1.0, 1.0]\ncell_size = 0.05\n[[material]]\nname = \"e\"\nmodel = \"linear-elastic\"\n"
    << "density = 1000.0\nyoung = 1000.0\npoisson = 0.3\n";
  for (const char* d : {"name = \"a\"\ncenter = [0.2, 0.2]\nvelocity = [0.1, 0.1]",
                        "name = \"b\"\ncenter = [0.8, 0.8]\nvelocity = [-0.1, -0.1]"})
    t << "[[body]]\nmaterial = \"e\"\nshape = \"disc\"\nradius = 0.2\n" << d << "\n";
  t << "[solver]\nend_time = 2.0\nintegrator = \"implicit\"\n[implicit]\nanalysis = \"dynamic\"\ntime_step = "
       "0.01\n";
  ImplicitRun run(t.str());
  double scale = 0.0;
  for (std::size_t p = 0; p < run.P.size(); ++p) scale += run.P.mass[p] * run.P.v[p].norm();
  double worst = 0.0;
  while (run.solver.time() < 2.0 - 1e-9) {
    ASSERT_TRUE(run.solver.step().ok);
    worst = std::max(worst, run.solver.totals().momentum.norm() / scale);
  }
  EXPECT_LT(worst, 1e-13);
  EXPECT_LT(run.solver.totals().kinetic_energy, 0.99 * 2.6);  // part of it is strain energy now
}

// The run driver: an implicit quasi-static stage brings the column to equilibrium in one load
// step, an explicit stage then starts from it at rest (the stresses, state and points handed
// over); series.csv has the iterations and residual of every step, summary.json the totals.
TEST(ImplicitRunDriver, ImplicitEquilibriumThenExplicitStage) {
  const std::string text = column_text(R"(
[implicit]
load_steps = 2
[[stage]]
name = "equilibrium"
duration = 1.0
integrator = "implicit"
[[stage]]
name = "hold"
duration = 0.01
)");
  test::TempDir dir;
  RunOptions opt;
  opt.progress = false;
  opt.threads = 2;
  const RunResult r = run_simulation(parse_scenario(text, "staged.toml"), dir.path(), opt);
  ASSERT_TRUE(r.completed) << r.message;
  ASSERT_EQ(r.stages.size(), 2u);
  const auto rows = test::series_rows(dir / "series.csv");
  ASSERT_GE(rows.size(), 4u);
  EXPECT_EQ(rows[1].at("iterations"), 1.0);
  EXPECT_LT(rows[1].at("residual"), 1e-10);
  EXPECT_EQ(rows.back().at("iterations"), 0.0);  // explicit rows
  // The explicit stage starts from equilibrium: its points barely move.
  EXPECT_LT(r.stages[1].max_displacement, 0.05 * kRho * kG * kH * kH / (2.0 * kM));
  std::ifstream in(dir / "summary.json");
  const std::string summary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(summary.find("\"implicit\": {\"geometry\": \"plane-strain\", \"analysis\": \"quasi-static\""),
            std::string::npos);
  EXPECT_NE(summary.find("\"steps\": 2, \"iterations\": 2"), std::string::npos);
  EXPECT_NE(summary.find("implicit_factorisation"), std::string::npos);
}

// A step that cannot converge is cut, and a run that cannot go on stops with a status naming
// the step; it is never accepted.
TEST(ImplicitRunDriver, AStepThatDoesNotConvergeStopsTheRun) {
  const std::string text = cylinder_text(0.025, 1e4, "model = \"tresca\"\ncohesion = 3e3",
                                         "max_iterations = 1\nmax_cuts = 2\nline_search = false\n");
  test::TempDir dir;
  RunOptions opt;
  opt.progress = false;
  const RunResult r = run_simulation(parse_scenario(text, "cut.toml"), dir.path(), opt);
  EXPECT_FALSE(r.completed);
  EXPECT_NE(r.message.find("did not converge after 2 cuts"), std::string::npos) << r.message;
  EXPECT_EQ(r.message.rfind("stopped at step ", 0), 0u) << r.message;
}

// Every interpolation of the explicit engine serves the implicit one: R2's settlement within
// 1 % in one load step and one iteration (the B-spline's clamped ends and quadrature GIMP's
// 4-node stencils included).
// With the cell-averaged volumetric strain too (B-bar: still linear, one iteration).
TEST(ImplicitColumn, EveryInterpolationSettlesTheColumn) {
  for (const char* volumetric : {"point", "cell-average"})
    for (const char* kernel : {"linear", "gimp", "gimp-quadrature", "bspline"}) {
      SCOPED_TRACE(volumetric);
      ImplicitRun run(
          column_text(std::string("[solver]\nend_time = 1.0\nintegrator = \"implicit\"\ninterpolation = \"") +
                      kernel + "\"\nvolumetric_strain = \"" + volumetric + "\"\n"));
      ASSERT_TRUE(run.run()) << kernel << ": " << run.failed.reason;
      EXPECT_EQ(run.solver.last_step().iterations, 1) << kernel;
      // The mass-weighted mean settlement against its closed form: u(y) = rho g (H y - y^2/2) / M
      // (exact at the points' positions, every kernel's points sit in the same places).
      double num = 0.0, exact = 0.0;
      for (std::size_t p = 0; p < run.P.size(); ++p) {
        const double y = run.P.x_ref[p][1];
        num += run.P.x_ref[p][1] - run.P.x[p][1];
        exact += kRho * kG * (kH * y - 0.5 * y * y) / kM;
      }
      EXPECT_NEAR(num, exact, 0.01 * exact) << kernel;
    }
}

// 3D: the column as a square prism between roller walls settles as in plane strain.
TEST(ImplicitColumn, ThreeDimensionalColumnSettlesAsTheOedometer) {
  const std::string text = R"(
[grid]
size = [0.02, 0.1, 0.02]
cell_size = 0.005
[[material]]
name = "soil"
model = "linear-elastic"
density = 1800.0
young = 1e6
poisson = 0.0
[[body]]
name = "column"
material = "soil"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.02, 0.1, 0.02]
[gravity]
acceleration = [0, -9.81, 0]
[boundary]
x_min = "roller"
x_max = "roller"
z_min = "roller"
z_max = "roller"
y_min = "fixed"
[solver]
end_time = 1.0
integrator = "implicit"
)";
  const Scenario3 s = std::get<Scenario3>(parse_any_scenario(text, "column3.toml"));
  Particles<3> P = build_particles(s);
  ImplicitSolver<3> solver(implicit_model(s), P, stage_materials(s, s.stages.front()), 2);
  solver.set_stage(s.stages.front().implicit, 1.0, 1.0);
  solver.begin_stage(stage_materials(s, s.stages.front()), 0.0);
  ASSERT_TRUE(solver.step().ok);
  EXPECT_EQ(solver.last_step().iterations, 1);
  double top = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) top = std::max(top, P.x_ref[p][1] - P.x[p][1]);
  const double exact = kRho * kG * kH * kH / (2.0 * kM);
  EXPECT_NEAR(top, exact, 0.01 * exact);
  EXPECT_NEAR(solver.energy().strain_energy, 0.5 * solver.energy().gravity_work,
              1e-9 * solver.energy().gravity_work);
}

// The iterative solver (CG with algebraic multigrid) gives the direct solver's answer.
TEST(ImplicitColumn, IterativeSolverAgreesWithTheDirectOne) {
  ImplicitRun direct(column_text("[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n"));
  ImplicitRun iterative(column_text(
      "[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n[implicit]\nlinear_solver = \"iterative\"\n"));
  ASSERT_TRUE(direct.run());
  ASSERT_TRUE(iterative.run()) << iterative.failed.reason;
  EXPECT_NE(iterative.solver.implicit_totals().linear_solver.find("gamg"), std::string::npos);
  for (std::size_t p = 0; p < direct.P.size(); ++p)
    EXPECT_NEAR(iterative.P.x[p][1], direct.P.x[p][1], 1e-6 * kRho * kG * kH * kH / kM);
}

// The implicit examples are valid and run their implicit stages (the cylinder to its end).
TEST(ImplicitExamples, HollowCylinderAndVerticalCutAreImplicit) {
  const std::string dir = std::string(SKRED_SOURCE_DIR) + "/examples/";
  const Scenario cut = std::get<Scenario>(load_any_scenario(dir + "vertical_cut_implicit.toml"));
  EXPECT_EQ(cut.stages.front().implicit.analysis, ImplicitAnalysis::Dynamic);
  const Scenario cyl = std::get<Scenario>(load_any_scenario(dir + "hollow_cylinder.toml"));
  EXPECT_EQ(cyl.geometry, Geometry::Axisymmetric);
  ASSERT_EQ(cyl.pressures.size(), 1u);
  test::TempDir out;
  RunOptions opt;
  opt.progress = false;
  const RunResult r = run_simulation(cyl, out.path(), opt);
  EXPECT_TRUE(r.completed) << r.message;
  EXPECT_EQ(r.steps, cyl.stages.front().implicit.load_steps);
}

// Checkpoint and restart serve the implicit integrator: a dynamic run (the bar of R1) stopped
// after step 20 and continued from its checkpoint writes the series of the run that was not
// stopped, bit for bit (one thread: the same sums in the same order).
TEST(ImplicitRunDriver, RestartContinuesADynamicRunBitForBit) {
  const std::string text = bar_text(20.0, "[output]\ninterval = 5.0\nseries_interval = 0.5\n");
  const Scenario s = parse_scenario(text, "bar.toml");
  test::TempDir dir;
  RunOptions opt;
  opt.progress = false;
  opt.threads = 1;
  opt.checkpoint_every = 1000000;
  const RunResult a = run_simulation(s, dir / "a", opt);
  ASSERT_TRUE(a.completed) << a.message;
  RunOptions stop = opt;
  stop.stop_at_step = 20;
  const RunResult b = run_simulation(s, dir / "b", stop);
  ASSERT_TRUE(b.interrupted) << b.message;
  RunOptions again = opt;
  again.restart = dir / "b" / "checkpoint.skc";
  const RunResult c = run_simulation(s, dir / "b", again);
  ASSERT_TRUE(c.completed) << c.message;
  EXPECT_EQ(c.steps, a.steps);
  auto read = [](const std::filesystem::path& f) {
    std::ifstream in(f);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  EXPECT_EQ(read(dir / "a" / "series.csv"), read(dir / "b" / "series.csv"));
}
