// The implicit integrator split among processes (issue 55), run under `mpirun -np 2` (and 4 by
// hand): each process holds a contiguous share of the points and the whole grid; the grid's sums
// (m_i, v_i, a_i, F_ext, F_int, the tangent) are every process's, and PETSc's parallel matrix and
// MUMPS solve on all of them. Each process also runs the problem alone, and the split run must
// take the same Newton iterations step by step and reach the same answer within the solver's
// tolerance: the R2 column quasi-static and dynamic (Newmark), in 2D and 3D, and the R6 cylinder
// (axisymmetric, a pressure on the inner face that follows the material) elastic and with Tresca
// yielding (the consistent tangent), and the vertical cut with the cell-averaged volumetric
// strain, and Acosta's remedies (W*, GM, DM, DM-G and CMPM's recovery, whose cells' point counts
// and patches are every process's). The split runs are checked against the closed forms too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

#include "../support.hpp"
#include "implicit/implicit_solver.hpp"
#include "parallel/point_shares.hpp"
#include "parallel/processes.hpp"
#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "scenario/initial_stress.hpp"
#include "scenario/scenario.hpp"

namespace skred {
namespace {

// What an implicit stage leaves: the Newton iterations of each step, the energies, and every
// point's reference and current position and stress (every process's, in rank order).
struct Outcome {
  std::vector<int> iterations;
  std::vector<double> energies;  // gravity work, strain energy, plastic dissipation, load work
  std::vector<double> x_ref, x, stress;
  std::vector<double> k_mag, f_mag;  // per grid node: K_mag and |F_int| (Acosta eq. 25-26)
  long points = 0;
  bool ok = true;
  std::string why;
};

// `odd`: the shares cut one point later than keep_share's, through a cell's points.
template <int D>
Outcome solve(const ScenarioOf<D>& s, const Processes& procs, bool odd = false) {
  Particles<D> P = build_particles(s);
  apply_initial_stress(s, P);
  if (!odd) {
    keep_share(P, procs);
  } else if (procs.distributed()) {
    const std::size_t n = P.size(), r = static_cast<std::size_t>(procs.rank()),
                      k = static_cast<std::size_t>(procs.size());
    const auto cut = [&](std::size_t q) { return q == 0 ? 0 : q == k ? n : n * q / k + 1; };
    std::vector<std::uint8_t> keep(n, 0);
    for (std::size_t p = cut(r); p < cut(r + 1); ++p) keep[p] = 1;
    P.erase(keep);
  }
  const Stage& st = s.stages.front();
  ImplicitModel<D> model = implicit_model(s);
  model.processes = procs;
  ImplicitSolver<D> solver(std::move(model), P, stage_materials(s, st), 1);
  solver.set_stage(st.implicit, stage_time_step(s, st), st.duration);
  solver.begin_stage(stage_materials(s, st), st.gravity_ramp_time);
  Outcome o;
  while (o.ok && solver.time() < st.duration - 1e-9 * solver.dt()) {
    const StepStatus k = solver.step();
    o.ok = k.ok;
    o.why = k.reason;
    o.iterations.push_back(solver.last_step().iterations);
  }
  solver.node_magnitudes(o.k_mag, o.f_mag);
  const EnergyTotals& e = solver.energy();
  o.energies = {e.gravity_work, e.strain_energy, e.plastic_dissipation, e.load_work};
  o.points = procs.sum_of(static_cast<long>(P.size()));
  std::vector<double> xr, x, sg;
  for (std::size_t p = 0; p < P.size(); ++p) {
    for (int d = 0; d < D; ++d) {
      xr.push_back(P.x_ref[p][d]);
      x.push_back(P.x[p][d]);
    }
    const Sym3 full = full_stress<D>(P.stress[p]);
    for (int c = 0; c < 6; ++c) sg.push_back(full[c]);
  }
  o.x_ref.assign(static_cast<std::size_t>(D * o.points), 0.0);
  o.x.assign(o.x_ref.size(), 0.0);
  o.stress.assign(static_cast<std::size_t>(6 * o.points), 0.0);
  procs.gather(xr.data(), xr.size(), o.x_ref.data(), o.x_ref.size());
  procs.gather(x.data(), x.size(), o.x.data(), o.x.size());
  procs.gather(sg.data(), sg.size(), o.stress.data(), o.stress.size());
  return o;
}

double largest(const std::vector<double>& v) {
  double m = 0.0;
  for (double a : v) m = std::max(m, std::abs(a));
  return m;
}

// The split run against one process's: the same iterations in every step; displacements,
// stresses and energies within `tol` of their scale (by default the displacement tolerance, 1e-10).
template <int D>
Outcome expect_same(const ScenarioOf<D>& s, const char* what, double tol = 1e-10, bool odd = false) {
  const Processes world = Processes::world();
  const Outcome one = solve<D>(s, Processes{});
  const Outcome all = solve<D>(s, world, odd);
  EXPECT_TRUE(one.ok) << what << ": " << one.why;
  EXPECT_TRUE(all.ok) << what << ": " << all.why;
  EXPECT_EQ(all.points, one.points) << what;
  EXPECT_EQ(all.iterations, one.iterations) << what << ": not the same Newton iterations";
  std::vector<double> u_one(one.x.size()), u_all(all.x.size());
  for (std::size_t i = 0; i < one.x.size(); ++i) {
    u_one[i] = one.x[i] - one.x_ref[i];
    u_all[i] = all.x[i] - all.x_ref[i];
  }
  const double u_scale = largest(u_one), s_scale = largest(one.stress), e_scale = largest(one.energies);
  EXPECT_GT(u_scale, 0.0) << what << ": nothing moved";
  double du = 0.0, ds = 0.0;
  for (std::size_t i = 0; i < u_one.size(); ++i) du = std::max(du, std::abs(u_all[i] - u_one[i]));
  for (std::size_t i = 0; i < one.stress.size(); ++i)
    ds = std::max(ds, std::abs(all.stress[i] - one.stress[i]));
  EXPECT_LE(du, tol * u_scale) << what << ": the displacements differ by up to " << du << " m";
  EXPECT_LE(ds, tol * s_scale) << what << ": the stresses differ by up to " << ds << " Pa";
  for (std::size_t i = 0; i < one.energies.size(); ++i)
    EXPECT_LE(std::abs(all.energies[i] - one.energies[i]), tol * e_scale) << what << ": energy " << i;
  // (the whole grid's magnitudes in the first process, which writes the grid's files)
  for (const auto& [a, b, name] :
       {std::tuple{&all.k_mag, &one.k_mag, "K_mag"}, std::tuple{&all.f_mag, &one.f_mag, "|F_int|"}}) {
    if (world.rank() != 0) break;
    EXPECT_EQ(a->size(), b->size()) << what << ": " << name;
    if (a->size() != b->size()) continue;
    const double scale = largest(*b);
    EXPECT_GT(scale, 0.0) << what << ": " << name;
    for (std::size_t i = 0; i < a->size(); ++i)
      EXPECT_LE(std::abs((*a)[i] - (*b)[i]), tol * scale) << what << ": " << name << " at node " << i;
  }
  long iterations = 0;
  for (int k : one.iterations) iterations += k;
  if (world.rank() == 0)
    std::printf(
        "%s on %d processes: %ld points, %zu steps, %ld iterations; displacements within %.1e, "
        "stresses within %.1e of their scale\n",
        what, world.size(), one.points, one.iterations.size(), iterations, du / u_scale, ds / s_scale);
  return all;
}

// R2's column (0.02 x 0.1 m, rho = 1800, E = 1 MPa, nu = 0, rollers beside, fixed base).
std::string column_text(const std::string& solver) { return test::r2_column_text(solver); }

constexpr double kRho = 1800.0, kG = 9.81, kH = 0.1, kM = 1e6;

// The top's settlement of a column's outcome (D components per point, axis 1 vertical).
double top_settlement(const Outcome& o, int D) {
  double top = 0.0;
  for (std::size_t i = 1; i < o.x.size(); i += static_cast<std::size_t>(D))
    top = std::max(top, o.x_ref[i] - o.x[i]);
  return top;
}

// R2 quasi-static in four load steps, Newton: the top settles by rho g H^2 / (2 M).
TEST(DistributedImplicit, ColumnR2QuasiStatic) {
  const Scenario s = parse_scenario(
      column_text("[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n[implicit]\nload_steps = 4\n"),
      "column.toml");
  const Outcome all = expect_same<2>(s, "R2 column, quasi-static");
  const double exact = kRho * kG * kH * kH / (2.0 * kM);
  EXPECT_NEAR(top_settlement(all, 2), exact, 0.01 * exact);
}

// R2 quasi-static with the iterative solver (CG with GAMG over the processes' rows): within the
// residual tolerance (1e-8; the Krylov solve stops at 1e-10 of its right-hand side, and the
// multigrid's coarsening is the processes').
TEST(DistributedImplicit, ColumnR2IterativeSolver) {
  const Scenario s =
      parse_scenario(column_text("[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n[implicit]\n"
                                 "load_steps = 4\nlinear_solver = \"iterative\"\n"),
                     "column.toml");
  const Outcome all = expect_same<2>(s, "R2 column, iterative", 1e-8);
  const double exact = kRho * kG * kH * kH / (2.0 * kM);
  EXPECT_NEAR(top_settlement(all, 2), exact, 0.01 * exact);
}

// R2 dynamic, gravity at once (Newmark, eq. 41-47), over 60 % of the first period.
TEST(DistributedImplicit, ColumnR2Dynamic) {
  const Scenario s = parse_scenario(
      column_text(
          "[solver]\nend_time = 0.01\nintegrator = \"implicit\"\n[implicit]\nanalysis = \"dynamic\"\n"),
      "column.toml");
  expect_same<2>(s, "R2 column, dynamic");
}

// R2 in 3D, one load step.
TEST(DistributedImplicit, ColumnR2In3D) {
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
  const Outcome all = expect_same<3>(s, "R2 column, 3D");
  const double exact = kRho * kG * kH * kH / (2.0 * kM);
  EXPECT_NEAR(top_settlement(all, 3), exact, 0.01 * exact);
}

// R6's cylinder (examples/hollow_cylinder.toml, 10 kPa): at r = 0.75 (a point's reference radius
// nearest it) sigma_r of eq. 34-36 within 2 % of p.
TEST(DistributedImplicit, CylinderR6Axisymmetric) {
  const std::string path = std::string(SKRED_SOURCE_DIR) + "/examples/hollow_cylinder.toml";
  const Scenario s = std::get<Scenario>(load_any_scenario(path));
  const Outcome all = expect_same<2>(s, "R6 cylinder");
  const double E = 1e6, nu = 0.3, p = 1e4, re2 = 1.5 * 1.5;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), G = E / (2 * (1 + nu));
  const auto sigma_r = [&](double r, double A1) {
    const double er = A1 * (1 + re2 / (r * r)), et = A1 * (1 - re2 / (r * r));
    return lambda * (er + et) + 2 * G * er;
  };
  const double A1 = -p / sigma_r(0.5, 1.0);
  std::size_t nearest = 0;
  for (std::size_t q = 0; q < static_cast<std::size_t>(all.points); ++q)
    if (std::abs(all.x_ref[2 * q] - 0.75) < std::abs(all.x_ref[2 * nearest] - 0.75)) nearest = q;
  const double r = all.x_ref[2 * nearest];
  EXPECT_NEAR(all.stress[6 * nearest], sigma_r(r, A1), 0.02 * p) << "at r = " << r;
}

// R6 with Tresca (s_u = 6 kPa) yielding around the inner wall: Newton with the consistent
// tangent takes the same iterations split as alone.
TEST(DistributedImplicit, CylinderR6YieldingWithTheConsistentTangent) {
  const std::string path = std::string(SKRED_SOURCE_DIR) + "/examples/hollow_cylinder.toml";
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const std::string from = "model = \"linear-elastic\"";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), "model = \"tresca\"\ncohesion = 6e3");
  // (the point strain: a yielding body's default is the cell-averaged one)
  text.replace(text.find("[solver]\n"), 9, "[solver]\nvolumetric_strain = \"point\"\n");
  const Scenario s = parse_scenario(text, path);
  const Outcome all = expect_same<2>(s, "R6 cylinder, Tresca");
  EXPECT_GT(all.energies[2], 0.0) << "no plastic dissipation: the cylinder did not yield";
}

// The vertical cut (examples/vertical_cut_implicit.toml: von Mises with softening, K0 stresses,
// dynamic, the cell-averaged volumetric strain of a slide, whose cells' sums are every
// process's) over its first 0.1 s, with the shares cut through cells.
TEST(DistributedImplicit, VerticalCutWithTheCellAveragedVolumetricStrain) {
  const std::string path = std::string(SKRED_SOURCE_DIR) + "/examples/vertical_cut_implicit.toml";
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const std::string from = "duration = 0.57";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), "duration = 0.1");
  const Scenario s = parse_scenario(text, path);
  ASSERT_TRUE(s.volumetric_averaging);
  const Outcome all = expect_same<2>(s, "vertical cut, cell-averaged", 1e-10, true);
  EXPECT_GT(all.energies[2], 0.0) << "no plastic dissipation: the cut did not yield";
}

// Acosta's remedies split among processes, with the shares cut through cells: R6 on Acosta's
// mesh (§3.1) with each integration of §5.2-5.4 and its default or named iteration. W* and DM
// weigh a point by its cell's count of points (cmp, eq. 15), which the processes add up; CMPM's
// patches follow the grid's masses; Acosta's stiffness cell by cell (App. C) sums each cell's
// W D_g A_g over the processes' points. CMPM cuts the recovery error by three (fig. 22: RMS of
// sigma_r against eq. 34 below 2.7 % of p, where at the points it is 8.1 %).
TEST(DistributedImplicit, CylinderR6WithAcostasRemedies) {
  struct Case {
    const char* name;
    std::string solver, implicit;
    bool cmpm;
  };
  const std::string linear = "interpolation = \"linear\"", gimp = "interpolation = \"gimp\"";
  const std::vector<Case> cases = {
      {"R6, W* with Newton", linear, "integration = \"modified-weights\"\niteration = \"newton\"", false},
      {"R6, GM with Acosta's iteration", linear, "integration = \"gauss-mapping\"\niteration = \"elastic\"",
       false},
      {"R6, DM-C with Acosta's load stepping", linear,
       "integration = \"double-mapping\"\nstress_recovery = \"cmpm\"", true},
      {"R6, DM-GC with Newton", gimp,
       "integration = \"double-mapping-gimp\"\nstress_recovery = \"cmpm\"\niteration = \"newton\"", true}};
  const double p = 1e4, nu = 0.3, re2 = 2.25, ri2 = 0.25;
  // Acosta App. A2 eq. 37-39 with E cancelled: sigma_r = A / r^2 + 2 C, sigma_r(r_i) = -p.
  const double C = -p / (2.0 * (1.0 - 2.0 * nu) * re2 / ri2 + 2.0);
  const double A = 2.0 * (1.0 - 2.0 * nu) * C * re2;
  for (const Case& c : cases) {
    const Scenario s = parse_scenario(test::acosta_cylinder_text(c.solver, c.implicit), "cylinder.toml");
    const Outcome all = expect_same<2>(s, c.name, 1e-10, true);
    double e = 0.0;
    for (std::size_t q = 0; q < static_cast<std::size_t>(all.points); ++q) {
      const double r = all.x_ref[2 * q];
      e += std::pow((all.stress[6 * q] - (A / (r * r) + 2.0 * C)) / p, 2);
    }
    e = std::sqrt(e / static_cast<double>(all.points));
    EXPECT_LT(e, c.cmpm ? 0.027 : 0.12) << c.name << ": sigma_r's RMS error against eq. 34";
  }
}

// R2's column with DM-GC under Newton (GIMP kernel): CMPM's recovery makes the column's stress
// exact (rho g (H - y) within 1e-6 of rho g H, RMS), split as alone.
TEST(DistributedImplicit, ColumnR2WithDmGcIsExact) {
  const Scenario s = parse_scenario(
      column_text(
          "[solver]\ninterpolation = \"gimp\"\nend_time = 1.0\nintegrator = \"implicit\"\n"
          "[implicit]\nload_steps = 1\niteration = \"newton\"\nintegration = \"double-mapping-gimp\"\n"
          "stress_recovery = \"cmpm\"\n"),
      "column.toml");
  const Outcome all = expect_same<2>(s, "R2 column, DM-GC", 1e-10, true);
  double e = 0.0;
  for (std::size_t q = 0; q < static_cast<std::size_t>(all.points); ++q)
    e += std::pow((all.stress[6 * q + 1] + kRho * kG * (kH - all.x_ref[2 * q + 1])) / (kRho * kG * kH), 2);
  EXPECT_LT(std::sqrt(e / static_cast<double>(all.points)), 1e-6);
}

// The vertical cut with Acosta's DM-GC under Newton (the paper's remedy for its shear band,
// §7.2; non-associated tangent: LU over the processes) over its first 0.1 s, shares cut through
// cells: yielding, sliver nodes and cut steps as alone.
TEST(DistributedImplicit, VerticalCutWithDmGc) {
  const std::string path = std::string(SKRED_SOURCE_DIR) + "/examples/vertical_cut_implicit.toml";
  std::string text = test::file_text(path);
  const std::string from = "duration = 0.57", key = "[implicit]\n";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), "duration = 0.1");
  ASSERT_NE(text.find(key), std::string::npos);
  text.replace(
      text.find(key), key.size(),
      key + "integration = \"double-mapping-gimp\"\nstress_recovery = \"cmpm\"\niteration = \"newton\"\n");
  const Scenario s = parse_scenario(text, path);
  const Outcome all = expect_same<2>(s, "vertical cut, DM-GC", 1e-10, true);
  EXPECT_GT(all.energies[2], 0.0) << "no plastic dissipation: the cut did not yield";
}

}  // namespace
}  // namespace skred
