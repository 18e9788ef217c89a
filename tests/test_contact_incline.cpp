// Frictional contact on inclines (Paper III §C.2.7, eq. C.36), reference R4: a block on a real
// sloped rigid body under vertical gravity slides with a = g (sin theta - mu cos theta) for
// mu < tan theta and stays at rest otherwise; the contact never creates energy.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <tuple>

#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "scenario/initial_stress.hpp"
#include "support.hpp"

using namespace skred;
using namespace skred::test;

namespace {
constexpr double g = 9.81;
constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

namespace {

// A block (0.4 m x 0.2 m, stiff elastic) on a rigid slab inclined at theta, vertical gravity;
// both bodies from a scenario file (the parser, the point builder and the solver settings of
// a real run). `offset` shifts the incline relative to the grid lines. Returns the mean travel
// of the block along the slope after `time` and checks the contact work every step.
struct InclineRun {
  double travel = 0;
  RuleWork rules;           // what the contact rule took, step by step
  double gravity_work = 0;  // over the run
  double half_travel = 0;   // the travel at half the time
};

std::string incline_text(double theta_deg, double mu, double offset, const char* scheme, double ramp,
                         const char* transfer = "flip") {
  const double th = theta_deg * kDeg, c = std::cos(th), s = std::sin(th);
  const Vec<2> a(0.1, 1.75 + offset);  // top of the incline
  const Vec<2> t(c, -s), n(s, c);      // downhill, normal
  const double L = 2.15 / c, thick = 0.15;
  auto pt = [](const Vec<2>& x) { return fmt::format("[{:.9f}, {:.9f}]", x[0], x[1]); };
  const Vec<2> b0 = a, b1 = a + L * t, b2 = b1 - thick * n, b3 = a - thick * n;
  const Vec<2> k0 = a + 0.35 * t, k1 = k0 + 0.4 * t, k2 = k1 + 0.2 * n, k3 = k0 + 0.2 * n;
  return fmt::format(R"(
[grid]
size = [2.3, 1.85]
cell_size = 0.05
[[material]]
name = "rock"
model = "linear-elastic"
density = 2000.0
young = 2e7
poisson = 0.0
[[body]]
name = "base"
rigid = true
material = "rock"
particles_per_cell = 4
shape = "polygon"
vertices = [{}, {}, {}, {}]
[[body]]
name = "block"
material = "rock"
particles_per_cell = 4
shape = "polygon"
vertices = [{}, {}, {}, {}]
[[contact]]
bodies = ["base", "block"]
friction = {}
[gravity]
acceleration = [0.0, -9.81]
ramp_time = {}
[solver]
scheme = "{}"
velocity_transfer = "{}"
time_step = 1.5e-4
end_time = 0.5
)",
                     pt(b0), pt(b1), pt(b2), pt(b3), pt(k0), pt(k1), pt(k2), pt(k3), mu, ramp, scheme,
                     transfer);
}

InclineRun incline(double theta_deg, double mu, double time, double offset = 0.0, const char* scheme = "usf",
                   bool outline = true, double ramp = 0.0, bool block_first = false,
                   const char* transfer = "flip") {
  std::string text = incline_text(theta_deg, mu, offset, scheme, ramp, transfer);
  if (block_first) {  // the block is the master, the rigid base the second body of the hierarchy
    const auto base = text.find("[[body]]\nname = \"base\""), block = text.find("[[body]]\nname = \"block\"");
    const auto end = text.find("[[contact]]");
    text = text.substr(0, base) + text.substr(block, end - block) + text.substr(base, block - base) +
           text.substr(end);
  }
  const int moving = block_first ? 0 : 1;
  const Scenario s = parse_scenario(text, "incline.toml");
  Particles<2> P = build_particles(s);
  SolverSettings<2> st = solver_settings(s);
  if (!outline) st.contact.outline_normal.assign(2, {});  // normals from the mass gradients
  ExplicitSolver<2> solver(scenario_grid(s), P, stage_materials(s, s.stages[0]), st, 1);
  EXPECT_TRUE(solver.contact_on());
  const Vec<2> t(std::cos(theta_deg * kDeg), -std::sin(theta_deg * kDeg));
  const auto travel = [&] {
    double u = 0.0;
    long n = 0;
    for (std::size_t p = 0; p < P.size(); ++p)
      if (P.body[p] == moving) {
        u += (P.x[p] - P.x_ref[p]).dot(t), ++n;
      } else {
        EXPECT_EQ(P.x[p], P.x_ref[p]);  // the rigid base does not move
      }
    return u / n;
  };
  const long steps = std::lround(time / solver.dt());
  InclineRun r;
  for (long k = 0; k < steps; ++k) {
    const StepStatus status = solver.step();
    EXPECT_TRUE(status.ok) << status.reason;
    if (!status.ok) break;
    r.rules.add(solver);
    if (k + 1 == steps / 2) r.half_travel = travel();
  }
  r.travel = travel();
  r.gravity_work = solver.energy().gravity_work;
  return r;
}

}  // namespace

// For mu < tan(theta) the block slides with a = g (sin theta - mu cos theta) (issue 11: within
// 2 %), at 20 and 30 degrees and at 27 degrees shifted off the grid lines by a third of a
// cell, with and without friction. The base is a rigid polygon, so its contact normal is
// its outline's (docs/method.md, "Contact"); the travel after 0.5 s must be within 2 % of
// a t^2 / 2 (measured: 0.02-0.07 % in every scheme, 4 x 4 points per cell). With the
// normals from the mass gradients instead (no outline) it is 4-16 % short, which fails
// this check. Friction never does negative work in a step.
struct InclineCase {
  double theta, mu, offset;
  const char* scheme = "usf";
  const char* transfer = "flip";
};
static double incline_error(const InclineCase& k, bool outline = true, bool block_first = false) {
  const double time = 0.5, c = std::cos(k.theta * kDeg);
  const double a = g * (std::sin(k.theta * kDeg) - k.mu * c);
  const double exact = 0.5 * a * time * time;
  const InclineRun r =
      incline(k.theta, k.mu, time, k.offset, k.scheme, outline, 0.0, block_first, k.transfer);
  const double error = (r.travel - exact) / exact;
  std::printf(
      "incline %.0f deg (offset %.4f m), mu %.1f, %s, %s%s%s: travel %.5f m, exact %.5f m (%+.2f %%)\n",
      k.theta, k.offset, k.mu, k.scheme, k.transfer, outline ? "" : ", mass-gradient normals",
      block_first ? ", block first" : "", r.travel, exact, 100 * error);
  EXPECT_GE(r.rules.min_rule, 0.0);  // the contact rule only stops motion
  EXPECT_LT(r.rules.dropped, 1e-4 * std::abs(r.gravity_work));
  return error;
}
static void check_incline(const InclineCase& k) { EXPECT_LT(std::abs(incline_error(k)), 0.02); }

TEST(ContactIncline, BlockSlidesWithTheAnalyticAcceleration30) {
  check_incline({30, 0.0, 0.0});
  check_incline({30, 0.2, 0.0});
}
TEST(ContactIncline, BlockSlidesWithTheAnalyticAcceleration20) {
  check_incline({20, 0.0, 0.0});
  check_incline({20, 0.2, 0.0});
}
TEST(ContactIncline, BlockSlidesWithTheAnalyticAccelerationOffGrid) {
  check_incline({27, 0.0, 0.0173});
  for (const char* scheme : {"usf", "usl", "averaged"}) check_incline({27, 0.3, 0.0173, scheme});
}
// The same law with the velocity transfers beyond FLIP (APIC, XPIC(2)): their nodal
// velocities v_i^{k+1} are the contact phase's coupled ones, per body.
TEST(ContactIncline, BlockSlidesWithTheAnalyticAccelerationApicXpic) {
  for (const char* transfer : {"apic", "xpic"})
    for (const char* scheme : {"usf", "averaged"}) check_incline({27, 0.3, 0.0173, scheme, transfer});
}

// A moving rigid incline (constant velocity u, 4 cells in 0.5 s) carrying the block, which
// starts with the same velocity: in the incline's frame (inertial) the block slides with
// a = g (sin theta - mu cos theta) as on a fixed incline (issue 11: within 2 %). The incline's
// exact normals move with it (its outline translated by u t); with the mass-gradient normals
// the travel is 4-16 % short (MassGradientNormalsActAsExtraFriction), which fails this check.
namespace {
// The block's travel along a rigid incline moving at u (0.4 m/s to the right), relative to the
// incline, after 0.5 s; with or without the outline's normals.
double moving_incline_travel(double theta, double mu, bool outline) {
  const double time = 0.5;
  const Vec<2> u(0.4, 0.0);
  std::string text = incline_text(theta, mu, 0.0173, "usf", 0.0);
  text.replace(text.find("size = [2.3, 1.85]"), 18, "size = [2.6, 1.85]");
  text.replace(text.find("rigid = true\n"), 13, "rigid = true\nvelocity = [0.4, 0.0]\n");
  text.replace(text.find("name = \"block\"\n"), 15, "name = \"block\"\nvelocity = [0.4, 0.0]\n");
  const Scenario s = parse_scenario(text, "moving_incline.toml");
  Particles<2> P = build_particles(s);
  SolverSettings<2> st = solver_settings(s);
  if (!outline) st.contact.outline_normal.assign(2, {});
  ExplicitSolver<2> solver(scenario_grid(s), P, stage_materials(s, s.stages[0]), st, 1);
  const long steps = std::lround(time / solver.dt());
  for (long k = 0; k < steps; ++k) {
    const StepStatus status = solver.step();
    EXPECT_TRUE(status.ok) << status.reason;
    if (!status.ok) return NAN;
    EXPECT_GE(solver.contact_step().rule_dissipation, 0.0);  // the contact rule only stops motion
  }
  const Vec<2> t(std::cos(theta * kDeg), -std::sin(theta * kDeg));
  double travel = 0.0;
  long n = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Vec<2> d = P.x[p] - P.x_ref[p] - solver.time() * u;  // relative to the incline
    if (P.body[p] == 1)
      travel += d.dot(t), ++n;
    else
      EXPECT_LT(d.norm(), 1e-9);  // the incline moved by u t
  }
  return travel / n;
}
}  // namespace

// A moving rigid incline (constant velocity, 4 cells in 0.5 s) carrying the block, which starts
// with the same velocity: in the incline's frame (inertial) the block slides with
// a = g (sin theta - mu cos theta) as on a fixed incline (issue 11: within 2 %). The incline's
// exact normals move with it (its outline translated by u t); with the mass-gradient normals
// instead the block falls short, as on the fixed incline (MassGradientNormalsActAsExtraFriction).
TEST(ContactIncline, MovingRigidInclineKeepsItsOutlineNormals) {
  const double theta = 27.0, mu = 0.2, time = 0.5;
  const double exact = 0.5 * g * (std::sin(theta * kDeg) - mu * std::cos(theta * kDeg)) * time * time;
  const double travel = moving_incline_travel(theta, mu, true),
               rough = moving_incline_travel(theta, mu, false);
  std::printf(
      "moving incline %.0f deg, mu %.1f: block travel on it %.5f m (mass-gradient normals %.5f m), "
      "exact %.5f m (%+.2f %%, %+.2f %%)\n",
      theta, mu, travel, rough, exact, 100 * (travel - exact) / exact, 100 * (rough - exact) / exact);
  EXPECT_NEAR(travel, exact, 0.02 * exact);
  EXPECT_LT(rough, 0.98 * exact);  // the moving outline's normals are what makes the difference
}

// The same with the block first in the [[body]] order: the block is the master, and the rigid
// base, second, takes its own outline's normal.
TEST(ContactIncline, RigidBaseBelowTheMasterKeepsItsOutlineNormal) {
  EXPECT_LT(std::abs(incline_error({27, 0.3, 0.0173}, true, true)), 0.02);
}

// Without an outline (a rigid body whose shape gives none, e.g. a layer) the normals come
// from the mass gradients, which scatter by a few degrees on a sloped staircase of points:
// that acts as extra friction, the travel is short by 4-16 % (here 6.5 %). Checked only
// that this fallback still slides and is not longer than the exact travel.
TEST(ContactIncline, MassGradientNormalsActAsExtraFriction) {
  const double error = incline_error({30, 0.2, 0.0}, false);
  EXPECT_LT(error, 0.0);
  EXPECT_GT(error, -0.1);
}

// For mu >= tan(theta) (tan 20 deg = 0.364, tan 27 deg = 0.510, tan 30 deg = 0.577) the block
// stays put. Gravity is ramped up over 0.1 s (Thesis eq. 4.13): applied at once it sets off
// elastic waves in the block that unload the interface for moments, and the block then
// ratchets down the slope by slips of a few um each (3.8 mm in 0.5 s at 30 deg, mu = 0.8, as
// a real elastic block under suddenly applied gravity would). Checked: the block moves less
// than 0.1 mm (the elastic shear of the block, measured 5-15 um), against 190-610 mm when it
// slides, and not at all (< 1 um) over the second half of the 0.5 s.
TEST(ContactIncline, BlockStaysPutWhenFrictionSuffices) {
  for (const auto& [theta, mu, offset] :
       {std::tuple{20.0, 0.5, 0.0}, std::tuple{30.0, 0.6, 0.0}, std::tuple{27.0, 0.55, 0.0173}}) {
    const InclineRun r = incline(theta, mu, 0.5, offset, "usf", true, 0.1);
    std::printf("incline %.0f deg (offset %.4f m), mu %.2f: travel %.3e m, over the second half %.3e m\n",
                theta, offset, mu, r.travel, r.travel - r.half_travel);
    EXPECT_LT(std::abs(r.travel), 1e-4);
    EXPECT_LT(std::abs(r.travel - r.half_travel), 1e-6);
    EXPECT_GE(r.rules.min_rule, 0.0);
  }
}
