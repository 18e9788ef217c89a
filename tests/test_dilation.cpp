// The dilation cut-off as a new continuum (Paper III §C.3.2; run/dilation_continuum.hpp,
// scenario/parser_dilation.cpp): the points of a sand body that reach the maximum void ratio
// join "<body>_dilated", which slides on the sand with mu = tan(phi). The move keeps mass and
// momentum, the new continuum follows the law of a block on an incline, a restart with it is
// bit for bit, and a bad key is named with file and line.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/checkpoint.hpp"
#include "run/checkpointing.hpp"
#include "run/dilation_continuum.hpp"
#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "scenario/initial_stress.hpp"
#include "support.hpp"
#include "temp_dir.hpp"

using namespace skred;
namespace fs = std::filesystem;

namespace {

constexpr double kG = 9.81;
constexpr double kRad = M_PI / 180.0;

// A sand column (friction 30, dilation 15 deg, e0 = 0.5, e_max = 0.52) collapsing on a rigid
// base with [[contact]]: its dilated continuum is on by default.
const char* kColumn = R"(
[grid]
size = [0.6, 0.3]
cell_size = 0.02
[[material]]
name = "sand"
model = "mohr-coulomb"
density = 1800.0
young = 2e6
poisson = 0.3
friction = 30.0
cohesion = 0.0
dilation = 15.0
initial_void_ratio = 0.5
max_void_ratio = 0.52
[[material]]
name = "rock"
model = "linear-elastic"
density = 2500.0
young = 2e6
poisson = 0.3
[[body]]
name = "base"
material = "rock"
rigid = true
shape = "rectangle"
min = [0.0, 0.0]
max = [0.6, 0.04]
[[body]]
name = "sand"
material = "sand"
shape = "rectangle"
min = [0.0, 0.04]
max = [0.1, 0.24]
[[contact]]
bodies = ["base", "sand"]
friction = 0.5
[gravity]
acceleration = [0.0, -9.81]
[boundary]
x_min = "roller"
[solver]
end_time = 0.2
)";

// Sums of the per-body nodal fields over the bodies and the nodes.
struct GridSums {
  double mass = 0.0;
  Vec<2> momentum = Vec<2>::Zero();
  double scale = 0.0;  // sum of |p_i|
};
GridSums grid_sums(const ExplicitSolver<2>& solver) {
  GridSums g;
  for (const BodyFields<2>& f : solver.body_fields())
    for (std::size_t i = 0; i < f.mass.size(); ++i) {
      g.mass += f.mass[i];
      g.momentum += f.momentum[i];
      g.scale += f.momentum[i].norm();
    }
  return g;
}

std::string read(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

// The scenario: a third body "sand_dilated" right after "sand" in the hierarchy, without
// points, sliding on the sand with tan(30 deg) and on the base as the sand does.
TEST(DilationContinuum, ScenarioAddsTheContinuum) {
  const Scenario s = parse_scenario(kColumn, "column.toml");
  ASSERT_EQ(s.bodies.size(), 3u);
  EXPECT_EQ(s.bodies[2].name, "sand_dilated");
  EXPECT_EQ(s.bodies[2].dilated_from, 1);
  const SolverSettings<2> st = solver_settings(s);
  ASSERT_TRUE(st.contact.enabled());
  EXPECT_EQ(st.contact.order, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(st.contact.parent, (std::vector<int>{-1, -1, 1}));
  EXPECT_DOUBLE_EQ(st.contact.mu(1, 2), std::tan(30.0 * kRad));
  EXPECT_EQ(st.contact.mu(0, 2), 0.5);
  EXPECT_EQ(st.contact.mu(0, 1), 0.5);
  Particles<2> P = build_particles(s);
  for (std::size_t p = 0; p < P.size(); ++p) EXPECT_NE(P.body[p], 2);  // it starts empty
  // An empty continuum is harmless: the solver steps, its volume per mass is the sand's.
  ExplicitSolver<2> solver(scenario_grid(s), P, stage_materials(s, s.stages[0]), st, 1);
  EXPECT_TRUE(solver.step().ok);
  EXPECT_GT(solver.volume_per_mass()[2], 0.0);
  EXPECT_EQ(solver.volume_per_mass()[2], solver.volume_per_mass()[1]);
  // Hierarchy with a body after the sand: the dilated sand comes before it.
  std::string text = kColumn;
  text.insert(text.find("[[contact]]"),
              "[[body]]\nname = \"lump\"\nmaterial = \"rock\"\nshape = \"rectangle\"\nmin = [0.4, 0.04]\n"
              "max = [0.5, 0.1]\n");
  const Scenario s2 =
      parse_scenario(text + "[[contact]]\nbodies = [\"sand\", \"lump\"]\nfriction = 0.2\n", "column.toml");
  ASSERT_EQ(s2.bodies.size(), 4u);
  const SolverSettings<2> st2 = solver_settings(s2);
  EXPECT_EQ(st2.contact.order, (std::vector<int>{0, 1, 3, 2}));
  EXPECT_EQ(st2.contact.mu(3, 2), 0.2);
  EXPECT_EQ(st2.contact.mu(0, 3), 0.5);
  // Without it (dilation_continuum = false) the run is as before: psi = 0 only.
  std::string off = kColumn;
  off.insert(off.find("[[contact]]"), "dilation_continuum = false\n");
  EXPECT_EQ(parse_scenario(off, "column.toml").bodies.size(), 2u);
}

// (a) A collapsing sand column: the points that reach the cut-off change continuum between
// steps; the points' mass and momentum are the same bit for bit, the bodies' nodal fields
// mapped afresh sum to the same to round-off; no point is lost, none moves back.
TEST(DilationContinuum, MoveKeepsMassAndMomentum) {
  const Scenario s = parse_scenario(kColumn, "column.toml");
  Particles<2> P = build_particles(s);
  ExplicitSolver<2> solver(scenario_grid(s), P, stage_materials(s, s.stages[0]), solver_settings(s), 1);
  const DilationContinua dilation(s);
  ASSERT_FALSE(dilation.empty());
  const std::size_t n = P.size();
  const double limit = std::log(1.52 / 1.5);
  long moved_total = 0, events = 0;
  for (long k = 0; k < 4000 && events < 20; ++k) {
    const ParticleTotals<2> before = solver.totals();
    const GridSums g0 = grid_sums(solver);
    std::vector<std::int16_t> body = P.body;
    const long moved = dilation.apply(P);
    if (moved > 0) {
      ++events;
      moved_total += moved;
      solver.particles_changed();
      ASSERT_TRUE(solver.map_grid().ok);
      const ParticleTotals<2> after = solver.totals();
      EXPECT_EQ(after.mass, before.mass);
      EXPECT_EQ(after.momentum, before.momentum);
      EXPECT_EQ(after.kinetic_energy, before.kinetic_energy);
      const GridSums g1 = grid_sums(solver);
      EXPECT_NEAR(g1.mass, g0.mass, 1e-13 * g0.mass);
      EXPECT_LE((g1.momentum - g0.momentum).norm(), 1e-13 * g0.scale + 1e-300);
      long changed = 0;
      for (std::size_t p = 0; p < n; ++p)
        if (body[p] != P.body[p]) {
          ++changed;
          EXPECT_EQ(body[p], 1);
          EXPECT_EQ(P.body[p], 2);
          EXPECT_GE(P.state[p].volume_strain, limit);
        }
      EXPECT_EQ(changed, moved);
    }
    for (std::size_t p = 0; p < n; ++p)
      if (body[p] == 2) {
        EXPECT_EQ(P.body[p], 2);  // never back
      }
    const StepStatus status = solver.step();
    ASSERT_TRUE(status.ok) << status.reason;
    ASSERT_EQ(P.size(), n);
  }
  std::printf("dilated continuum: %ld points moved in %ld steps with moves, t = %.3f s\n", moved_total,
              events, solver.time());
  EXPECT_GE(events, 1);
  EXPECT_EQ(dilation.count(P), moved_total);
}

// (b) The dilated continuum slides on its parent with mu = tan(phi): a stiff block of it on a
// layer of the parent sand (one body, a strong cohesion keeps both elastic) under gravity
// tilted by theta = 30 deg, phi = 20 deg: a = g (sin theta - tan(phi) cos theta), travel a
// t^2 / 2 within 2 % (as ContactLayers.BlockSlidesOnADeformableLayer for a [[contact]] pair).
TEST(DilationContinuum, SlidesOnTheParentWithTanPhi) {
  const double th = 30.0 * kRad, phi = 20.0 * kRad, t = 0.3;
  const std::string text = fmt::format(R"(
[grid]
size = [2.1, 0.4]
cell_size = 0.05
[[material]]
name = "sand"
model = "mohr-coulomb"
density = 2000.0
young = 2e7
poisson = 0.0
friction = 20.0
cohesion = 1e6
dilation = 0.0
initial_void_ratio = 0.5
max_void_ratio = 0.8
[[body]]
name = "sand"
material = "sand"
dilation_continuum = true
shape = "polygon"
vertices = [[0.0, 0.0], [2.0, 0.0], [2.0, 0.15], [0.8, 0.15], [0.8, 0.35], [0.4, 0.35], [0.4, 0.15],
            [0.0, 0.15]]
[gravity]
acceleration = [{}, {}]
[boundary]
y_min = "fixed"
[solver]
end_time = {}
scheme = "usf"
)",
                                       kG * std::sin(th), -kG * std::cos(th), t);
  const Scenario s = parse_scenario(text, "incline.toml");
  ASSERT_EQ(s.bodies.size(), 2u);
  Particles<2> P = build_particles(s);
  const double base = 0.15, H = 0.2;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const bool block = P.x[p][1] > base;
    if (block) P.state[p].volume_strain = 1.0;               // past the cut-off: the mover takes it
    const double d = (block ? base + H : base) - P.x[p][1];  // an infinite layer's stress, each alone
    P.stress[p][1] = -2000.0 * kG * std::cos(th) * d;
    P.stress[p][3] = 2000.0 * kG * std::sin(th) * d;
  }
  const DilationContinua dilation(s);
  const long moved = dilation.apply(P);
  EXPECT_EQ(moved, std::count_if(P.x.begin(), P.x.end(), [&](const Vec<2>& x) { return x[1] > base; }));
  SolverSettings<2> st = solver_settings(s);
  EXPECT_DOUBLE_EQ(st.contact.mu(0, 1), std::tan(phi));
  st.dt = 0.2 * 0.05 / s.materials[0].wave_speed();
  ExplicitSolver<2> solver(scenario_grid(s), P, stage_materials(s, s.stages[0]), st, 1);
  const long steps = std::lround(t / st.dt);
  for (long k = 0; k < steps; ++k) ASSERT_TRUE(solver.step().ok);
  double u = 0;
  long n = 0;
  for (std::size_t p = 0; p < P.size(); ++p)
    if (P.body[p] == 1) u += P.x[p][0] - P.x_ref[p][0], ++n;
  u /= n;
  const double exact = 0.5 * kG * (std::sin(th) - std::tan(phi) * std::cos(th)) * t * t;
  std::printf("dilated block on its sand, theta 30, phi 20: travel %.5f m, exact %.5f m (%+.2f %%)\n", u,
              exact, 100 * (u - exact) / exact);
  EXPECT_NEAR(u, exact, 0.02 * exact);
}

// (c) Checkpoint and restart with points in the dilated continuum: the restarted run ends bit
// for bit where the uninterrupted one ends; summary.json counts the moved points.
TEST(DilationContinuum, RestartIsBitForBit) {
  const fs::path dir = skred::test::fresh_temp_dir("dilation");
  std::string text = kColumn;
  text.replace(text.find("end_time = 0.2"), 14, "end_time = 0.06\n[output]\ninterval = 0.02");
  std::ofstream(dir / "column.toml") << text;
  const Scenario s = load_scenario((dir / "column.toml").string());
  RunOptions opt;
  opt.progress = false;
  opt.threads = 1;
  opt.checkpoint_every = 1000000;  // only the final one
  const RunResult a = run_simulation(s, dir / "a", opt);
  ASSERT_TRUE(a.completed) << a.message;
  ASSERT_EQ(a.stages.size(), 1u);
  ASSERT_GT(a.stages[0].dilated_points, 0);
  ASSERT_TRUE(a.stages[0].dilated_first_time.has_value());
  const std::string summary = read(dir / "a" / "summary.json");
  EXPECT_NE(summary.find(fmt::format("\"dilated_points\": {}", a.stages[0].dilated_points)),
            std::string::npos);
  const double dt = a.simulated_time / static_cast<double>(a.steps);
  const long first = std::lround(*a.stages[0].dilated_first_time / dt);
  ASSERT_LT(first + 10, a.steps);

  RunOptions stop = opt;  // after the first points moved
  stop.stop_at_step = (first + a.steps) / 2;
  ASSERT_TRUE(run_simulation(s, dir / "b", stop).interrupted);
  RunOptions again = opt;
  again.restart = dir / "b" / "checkpoint.skc";
  const RunResult c = run_simulation(s, dir / "b", again);
  ASSERT_TRUE(c.completed) << c.message;
  EXPECT_EQ(c.steps, a.steps);
  Particles<2> A, B;
  SolverClock ca, cb;
  RunProgress<2> pa, pb;
  std::vector<SeriesRow> ra, rb;
  load_checkpoint(dir / "a" / "checkpoint.skc", s, A, ca, pa, ra);
  load_checkpoint(dir / "b" / "checkpoint.skc", s, B, cb, pb, rb);
  A.for_each_field([&](const auto& f, const auto& fa) {
    const auto& fb = B.*(f.member);
    ASSERT_EQ(fa.size(), fb.size()) << f.name;
    if constexpr (std::is_same_v<std::decay_t<decltype(fa[0])>, PointState>) {
      for (std::size_t i = 0; i < fa.size(); ++i)  // member by member: no padding
        EXPECT_TRUE(
            !std::memcmp(&fa[i].plastic_shear_strain, &fb[i].plastic_shear_strain, 3 * sizeof(double)) &&
            fa[i].yielding == fb[i].yielding)
            << "state of point " << i;
    } else {
      EXPECT_TRUE(fa.empty() || std::memcmp(fa.data(), fb.data(), fa.size() * sizeof(fa[0])) == 0)
          << "field " << f.name;
    }
  });
  EXPECT_EQ(std::memcmp(&ca, &cb, sizeof(SolverClock)), 0);
  EXPECT_EQ(read(dir / "a" / "series.csv"), read(dir / "b" / "series.csv"));
  EXPECT_EQ(c.stages[0].dilated_points, a.stages[0].dilated_points);
  EXPECT_EQ(c.stages[0].dilated_first_time, a.stages[0].dilated_first_time);
  EXPECT_EQ(c.stages[0].dilated_last_time, a.stages[0].dilated_last_time);
  fs::remove_all(dir);
}

// (d) Bad input: the key is named with file and line.
TEST(DilationContinuum, BadKeysAreNamed) {
  auto error = [](std::string text, const std::string& insert_before, const std::string& line) {
    text.insert(text.find(insert_before), line);
    try {
      parse_scenario(text, "bad.toml");
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // A rigid body, a material without the cut-off (the rock), a wrong type
  std::string e = error(kColumn, "shape = \"rectangle\"\nmin = [0.0, 0.0]", "dilation_continuum = true\n");
  EXPECT_NE(e.find("bad.toml:"), std::string::npos) << e;
  EXPECT_NE(e.find("body[0].dilation_continuum"), std::string::npos) << e;
  EXPECT_NE(e.find("rigid"), std::string::npos) << e;
  std::string no_cutoff = kColumn;
  no_cutoff.replace(no_cutoff.find("rigid = true\n"), 13, "");
  e = error(no_cutoff, "shape = \"rectangle\"\nmin = [0.0, 0.0]", "dilation_continuum = true\n");
  EXPECT_NE(e.find("bad.toml:"), std::string::npos) << e;
  EXPECT_NE(e.find("material \"rock\" has no dilation cut-off"), std::string::npos) << e;
  e = error(kColumn, "shape = \"rectangle\"\nmin = [0.0, 0.04]", "dilation_continuum = 1\n");
  EXPECT_NE(e.find("body[1].dilation_continuum"), std::string::npos) << e;
  // The name of the new body is taken
  e = error(
      kColumn, "[[contact]]",
      "[[body]]\nname = \"sand_dilated\"\nmaterial = \"rock\"\nshape = \"rectangle\"\nmin = [0.4, 0.04]\n"
      "max = [0.5, 0.1]\n");
  EXPECT_NE(e.find("bad.toml:"), std::string::npos) << e;
  EXPECT_NE(e.find("\"sand_dilated\", the name of another body"), std::string::npos) << e;
}

// A lone dilated point in a sand layer at rest under gravity moves with the sand around it
// (kDilatedFill): its continuum has no neighbours to balance its stress, so it has no contact
// of its own there; it stays put as the sand does. (With the merge off, kDilatedFill = 0, the
// point reached 1.7 m/s and moved 9 cm in these 0.2 s.)
TEST(DilationContinuum, ALonePointMovesWithTheSand) {
  const std::string text = R"(
[grid]
size = [1.0, 0.4]
cell_size = 0.05
[[material]]
name = "sand"
model = "mohr-coulomb"
density = 2000.0
young = 2e7
poisson = 0.0
friction = 30.0
cohesion = 1e6
initial_void_ratio = 0.5
max_void_ratio = 0.8
[[body]]
name = "sand"
material = "sand"
particles_per_cell = 3
dilation_continuum = true
shape = "rectangle"
min = [0.0, 0.0]
max = [1.0, 0.3]
[gravity]
acceleration = [0.0, -9.81]
[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"
[solver]
end_time = 0.2
)";
  const Scenario s = parse_scenario(text, "layer.toml");
  Particles<2> P = build_particles(s);
  std::size_t lone = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    P.stress[p][1] = -2000.0 * kG * (0.3 - P.x[p][1]);  // the layer's stress (nu = 0)
    if ((P.x[p] - Vec<2>(0.5, 0.15)).norm() < (P.x[lone] - Vec<2>(0.5, 0.15)).norm()) lone = p;
  }
  P.state[lone].volume_strain = 1.0;
  ASSERT_EQ(DilationContinua(s).apply(P), 1);
  ExplicitSolver<2> solver(scenario_grid(s), P, stage_materials(s, s.stages[0]), solver_settings(s), 1);
  const long steps = std::lround(0.2 / solver.dt());
  double fastest = 0.0;
  for (long k = 0; k < steps; ++k) {
    ASSERT_TRUE(solver.step().ok);
    fastest = std::max(fastest, P.v[lone].norm());
  }
  const double moved = (P.x[lone] - P.x_ref[lone]).norm();
  std::printf("lone dilated point in a layer at rest: fastest %.2e m/s, moved %.2e m\n", fastest, moved);
  EXPECT_EQ(P.body[lone], 1);
  EXPECT_LT(fastest, 1e-2);
  EXPECT_LT(moved, 1e-4);
}
