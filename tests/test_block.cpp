// Reference R4: a stiff block on a frictional base (Thesis eq. 5.8-5.11). Gravity tilted by
// theta is an incline of angle theta: for mu < tan(theta) the block slides with
// a = g (sin(theta) - mu cos(theta)), s = a t^2 / 2; for mu >= tan(theta) it stays put.
// Horizontal variant: initial speed v0 stops after v0^2 / (2 mu g).
#include <gtest/gtest.h>

#include <numbers>

#include "support.hpp"

using namespace skred;
using namespace skred::test;

namespace {

constexpr double g = 9.81;

// The velocity transfer of a run: the seeds' FLIP, or the slide default (docs/method.md, "The
// defaults": XPIC(2) once per 2 h/c with the cell-averaged volumetric strain).
enum class BlockTransfer { Flip, SlideDefault };

// Runs the block for `time` seconds and returns the mean displacement along x.
double slide(double theta_deg, double mu, double v0, double time, Interpolation interp,
             BlockTransfer transfer = BlockTransfer::Flip) {
  const double th = theta_deg * std::numbers::pi / 180.0;
  const Material m = elastic(2000.0, 1e8, 0.0);
  const double h = 0.05, H = 0.2;
  Particles<2> P;
  fill_rectangle(P, m, h, 2, 0.1, 0.0, 0.5, H, Vec<2>(v0, 0.0));
  // Start from the block's static stress so that no elastic wave is set off.
  // (an infinite layer's stress: sigma_yy = -rho g cos(theta) d, sigma_xy = rho g sin(theta) d).
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double d = H - P.x[p][1];
    P.stress[p][1] = -m.density * g * std::cos(th) * d;
    if (v0 == 0.0) P.stress[p][3] = m.density * g * std::sin(th) * d;
  }
  SolverSettings<2> st;
  st.interpolation = interp;
  st.scheme = StressScheme::USF;
  st.dt = 0.2 * h / m.wave_speed();
  if (transfer == BlockTransfer::SlideDefault) {
    st.velocity_transfer = VelocityTransfer::Xpic;
    st.xpic_period = 2.0 * h / m.wave_speed();
    st.volumetric_averaging = true;
  }
  st.gravity = Vec<2>(g * std::sin(th), -g * std::cos(th));
  st.boundaries = {side(BoundaryKind::Free), side(BoundaryKind::Free), side(BoundaryKind::Friction, mu),
                   side(BoundaryKind::Free)};
  ExplicitSolver<2> solver(grid2(h, 40, 6), P, {m}, st, 1);
  const long steps = std::lround(time / st.dt);
  for (long s = 0; s < steps; ++s) {
    const auto status = solver.step();
    EXPECT_TRUE(status.ok) << status.reason;
    if (!status.ok) break;
  }
  double u = 0;
  for (std::size_t p = 0; p < P.size(); ++p) u += P.x[p][0] - P.x_ref[p][0];
  return u / P.size();
}

}  // namespace

TEST(FrictionalBlock, SlidesWithTheAnalyticAcceleration) {
  const double t = 0.5;
  for (double mu : {0.0, 0.2, 0.4}) {
    const double th = 30.0 * std::numbers::pi / 180.0;
    const double exact = 0.5 * g * (std::sin(th) - mu * std::cos(th)) * t * t;
    for (Interpolation interp : {Interpolation::Gimp, Interpolation::Linear}) {
      const double s = slide(30.0, mu, 0.0, t, interp);
      std::printf("theta 30, mu %.1f, %s: travel %.5f m, exact %.5f m (%.2f %%)\n", mu, to_string(interp), s,
                  exact, 100 * (s - exact) / exact);
      EXPECT_NEAR(s, exact, 0.02 * exact);
    }
  }
}

TEST(FrictionalBlock, StaysPutWhenFrictionSuffices) {
  // The closed form sets the bound. A block whose friction fell 1 % short of the threshold,
  // mu = 0.99 tan(theta), would slide s = g (sin(theta) - mu cos(theta)) t^2 / 2 = 0.01 g
  // sin(theta) t^2 / 2: 6.13 mm in 0.5 s at 30 deg. With friction 1 % above the threshold (and
  // with more) the block must hold: its travel below 5 % of that, 0.31 mm.
  // Under the slide default (XPIC(2) once per 2 h/c with the cell-averaged volumetric strain;
  // docs/method.md, "The defaults"), measured: 0.104 mm at mu = 1.01 tan(theta) (1.7 % of the
  // 1 % deficit's slide), 4.6 um at 0.8, 2.8 um at 1.0.
  // Not asserted, recorded: under plain FLIP the undamped block does not hold near the
  // threshold. The points next to the wall keep velocities the wall nodes do not have ("How FLIP
  // lifts the block"), and the uphill edge ratchets downhill: 34.8 mm in 0.5 s at mu = 1.01
  // tan(theta) (5.7 times the 1 % deficit's slide), 24.0 mm at mu = 0.6 (4 % above). Even on a
  // mu = 10 wall, where the block cannot slip, its kinetic energy grows under FLIP (wall chatter):
  // 1.1e-4 J at 10 ms, 1.5e-3 J at 0.1 s, 2.9e-2 J at 1.5 s (under the slide default it decays
  // to 1.7e-15 J); an earlier look found the energy balance not closing there.
  const double th = 30.0 * std::numbers::pi / 180.0, t = 0.5;
  const double deficit = 0.5 * g * (std::sin(th) - 0.99 * std::tan(th) * std::cos(th)) * t * t;
  for (double mu : {1.01 * std::tan(th), 0.8, 1.0}) {
    const double s = slide(30.0, mu, 0.0, t, Interpolation::Gimp, BlockTransfer::SlideDefault);
    std::printf("theta 30, mu %.4f: travel %.3e m, %.2f %% of the 1 %% deficit's slide (%.3e m)\n", mu, s,
                100 * s / deficit, deficit);
    EXPECT_LT(std::abs(s), 0.05 * deficit) << "mu = " << mu;
  }
}

TEST(FrictionalBlock, HorizontalBlockStopsAtTheAnalyticDistance) {
  const double v0 = 1.0, mu = 0.5;
  const double stop = v0 * v0 / (2 * mu * g);  // 0.102 m after 0.204 s
  const double s = slide(0.0, mu, v0, 0.4, Interpolation::Gimp);
  std::printf("horizontal: stopping distance %.5f m, exact %.5f m\n", s, stop);
  EXPECT_NEAR(s, stop, 0.02 * stop);
}
