// Reference R3: colliding elastic discs (Sulsky et al. 1994; Thesis §2.1, fig. 4.6).
// Unit square, E = 1000, nu = 0.3, rho = 1000, discs of radius 0.2 at (0.2, 0.2) and
// (0.8, 0.8) moving at +-(0.1, 0.1); 20 x 20 cells, 2 x 2 points per cell, dt = 0.001.
// Invariants: total momentum 0, mass constant; the discs rebound; the averaged scheme
// conserves kinetic + strain energy (eq. 4.15-4.17), update-stress-last dissipates.
#include <gtest/gtest.h>

#include "support.hpp"

using namespace skred;
using namespace skred::test;

namespace {

struct DiscRun {
  double mass0, mass1, max_momentum, e0, e_end, min_e, ke_min;
  double vx_disc0_end;
};

DiscRun run_discs(StressScheme scheme, Interpolation interp = Interpolation::Gimp) {
  const Material m = elastic(1000.0, 1000.0, 0.3);
  const double h = 0.05;
  Particles<2> P;
  fill_disc(P, m, h, 2, Vec<2>(0.2, 0.2), 0.2, 1.0, Vec<2>(0.1, 0.1), 0);
  fill_disc(P, m, h, 2, Vec<2>(0.8, 0.8), 0.2, 1.0, Vec<2>(-0.1, -0.1), 1);
  SolverSettings<2> st;
  st.interpolation = interp;
  st.scheme = scheme;
  st.dt = 0.001;
  ExplicitSolver<2> solver(grid2(h, 20, 20), P, {m}, st, 1);
  DiscRun r{};
  const auto t0 = solver.totals();
  r.mass0 = t0.mass;
  r.e0 = t0.kinetic_energy;
  r.min_e = r.e0;
  r.ke_min = r.e0;
  for (int s = 0; s < 3000; ++s) {
    const StepStatus status = solver.step();
    EXPECT_TRUE(status.ok) << status.reason;
    if (!status.ok) break;
    const auto t = solver.totals();
    r.max_momentum = std::max(r.max_momentum, t.momentum.norm());
    const double e = t.kinetic_energy + solver.energy().strain_energy;
    r.min_e = std::min(r.min_e, e);
    r.ke_min = std::min(r.ke_min, t.kinetic_energy);
  }
  const auto t = solver.totals();
  r.mass1 = t.mass;
  r.e_end = t.kinetic_energy + solver.energy().strain_energy;
  double px = 0, m0 = 0;
  for (std::size_t p = 0; p < P.size(); ++p)
    if (P.body[p] == 0) {
      px += P.mass[p] * P.v[p][0];
      m0 += P.mass[p];
    }
  r.vx_disc0_end = px / m0;
  return r;
}

}  // namespace

TEST(CollidingDiscs, AveragedSchemeConservesEnergyAndMomentum) {
  const DiscRun r = run_discs(StressScheme::Averaged);
  EXPECT_EQ(r.mass0, r.mass1);  // mass exactly
  // momentum to round-off (zero by the discs' mirror symmetry too: with unequal speeds in
  // VelocityTransfer.MomentumIsConservedToRoundOffByEveryTransferAndScheme)
  EXPECT_LT(r.max_momentum, 1e-12 * r.mass0 * 0.1);
  EXPECT_LT(r.ke_min, 0.5 * r.e0);   // a real collision took place
  EXPECT_LT(r.vx_disc0_end, -0.05);  // disc 0 rebounds (moves back)
  const double change = std::abs(r.e_end - r.e0) / r.e0;
  const double worst = (r.e0 - r.min_e) / r.e0;
  std::printf(
      "averaged: initial KE %.5f (exact 2.5133 for the continuous discs), energy change %.3f %%, "
      "largest dip %.3f %%, rebound velocity %.4f\n",
      r.e0, 100 * change, 100 * worst, r.vx_disc0_end);
  EXPECT_LT(change, 0.01);
  EXPECT_LT(worst, 0.01);
}

// How much each scheme loses. With R3's small time step (c dt / h = 0.02) the remapped
// update-stress-last scheme loses little energy over the whole collision, but it dips while
// the discs are in contact; the averaged scheme holds kinetic + strain energy constant
// throughout (Thesis fig. 4.6).
TEST(CollidingDiscs, SchemesCompared) {
  for (Interpolation interp : {Interpolation::Linear, Interpolation::Gimp}) {
    const DiscRun avg = run_discs(StressScheme::Averaged, interp);
    const DiscRun usl = run_discs(StressScheme::USL, interp);
    const DiscRun usf = run_discs(StressScheme::USF, interp);
    auto loss = [](const DiscRun& r) { return 100 * (r.e0 - r.e_end) / r.e0; };
    auto dip = [](const DiscRun& r) { return 100 * (r.e0 - r.min_e) / r.e0; };
    std::printf(
        "%s: energy lost over the run / largest dip during contact: USL %.3f %% / %.3f %%, "
        "USF %.3f %% / %.3f %%, averaged %.3f %% / %.3f %%\n",
        to_string(interp), loss(usl), dip(usl), loss(usf), dip(usf), loss(avg), dip(avg));
    EXPECT_LT(usl.max_momentum, 1e-12 * usl.mass0 * 0.1);
    EXPECT_LT(std::abs(loss(avg)), 1.0);
    EXPECT_GT(dip(usl), 0.05);
    EXPECT_LT(dip(avg), 0.2 * dip(usl));
    EXPECT_LT(usl.vx_disc0_end, -0.05);
    EXPECT_LT(usf.vx_disc0_end, -0.05);
  }
}

// The last phase of a step maps the next step's mass and momentum (and stores the points'
// weighting functions) as it moves the points. A run that maps afresh at the start of every
// step, as the algorithm is written in Thesis §4.4, must give the same points bit for bit,
// for every scheme and kernel.
TEST(CollidingDiscs, FusedMapEqualsAFreshMapEveryStep) {
  const Material m = elastic(1000.0, 1000.0, 0.3);
  const double h = 0.05;
  for (StressScheme scheme : {StressScheme::USF, StressScheme::USL, StressScheme::Averaged})
    for (Interpolation interp : {Interpolation::Linear, Interpolation::Gimp, Interpolation::Bspline,
                                 Interpolation::GimpQuadrature}) {
      Particles<2> fused, fresh;
      for (Particles<2>* P : {&fused, &fresh}) {
        fill_disc(*P, m, h, 2, Vec<2>(0.2, 0.2), 0.2, 1.0, Vec<2>(0.1, 0.1), 0);
        fill_disc(*P, m, h, 2, Vec<2>(0.8, 0.8), 0.2, 1.0, Vec<2>(-0.1, -0.1), 1);
      }
      SolverSettings<2> st;
      st.interpolation = interp;
      st.scheme = scheme;
      st.dt = 0.001;
      ExplicitSolver<2> a(grid2(h, 20, 20), fused, {m}, st, 2), b(grid2(h, 20, 20), fresh, {m}, st, 2);
      for (int s = 0; s < 400; ++s) {
        ASSERT_TRUE(a.step().ok);
        b.particles_changed();
        ASSERT_TRUE(b.step().ok);
      }
      double worst = 0.0;
      for (std::size_t p = 0; p < fused.size(); ++p)
        worst = std::max({worst, (fused.x[p] - fresh.x[p]).norm(), (fused.v[p] - fresh.v[p]).norm(),
                          (fused.stress[p] - fresh.stress[p]).norm()});
      EXPECT_EQ(worst, 0.0) << to_string(interp) << " " << static_cast<int>(scheme);
      EXPECT_EQ(a.energy().strain_energy, b.energy().strain_energy);
    }
}

namespace {

// The stored energy of the points recomputed from their state: the energy of the elastic law
// (stress_update.hpp) at F, sum V0 (G sum (l_i - 1)^2 + lambda/2 (sum (l_i - 1))^2) with the
// principal stretches l_i (l_3 = 1 in plane strain) -- and, printed beside it, the small-strain
// complementary energy of the stress, sum V sigma : C^-1 : sigma / 2 (>= 0). At R3's squeeze of
// about 25 % that one is no second way: it differs from the law's energy by 24 % of the peak.
std::pair<double, double> stored_from_state(const Particles<2>& P, const Material& m) {
  const double E = m.elastic.young, nu = m.elastic.poisson;
  const double G = E / (2 * (1 + nu)), lam = E * nu / ((1 + nu) * (1 - 2 * nu));
  double law = 0, comp = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Mat<2> B = P.F[p] * P.F[p].transpose();  // principal stretches squared: its eigenvalues
    const double m = 0.5 * B.trace(), r = std::sqrt(std::max(m * m - B.determinant(), 0.0));
    const double e1 = std::sqrt(m + r) - 1.0, e2 = std::sqrt(B.determinant() / (m + r)) - 1.0;
    law += P.volume0[p] * (0.5 * lam * (e1 + e2) * (e1 + e2) + G * (e1 * e1 + e2 * e2));
    const auto& s = P.stress[p];
    const double tr = s[0] + s[1] + s[2], ss = s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2 * s[3] * s[3];
    comp += 0.5 * P.volume0[p] * P.F[p].determinant() * ((1 + nu) * ss - nu * tr * tr) / E;
  }
  return {law, comp};
}

}  // namespace

// R3 with energy computed two ways (issue 12): the strain energy accumulated step by step
// (eq. 4.16) against the stored energy recomputed from the points' state, every 100 steps.
// The discs are squeezed by about 25 %, so an elastic law that is not hyperelastic (sigma^k +
// C : d_eps pushed forward through dF) does work in a closed cycle: before the fix the
// accumulated energy ended at -0.126 J while the kinetic energy after the rebound was 2.726 J
// against 2.600 J before (+4.8 %). No energy from nowhere: kinetic energy after the
// separation <= before, stored energy >= 0 throughout, the two ways agree.
TEST(CollidingDiscs, StoredEnergyTwoWaysAndNoEnergyFromNowhere) {
  const Material m = elastic(1000.0, 1000.0, 0.3);
  const double h = 0.05;
  Particles<2> P;
  fill_disc(P, m, h, 2, Vec<2>(0.2, 0.2), 0.2, 1.0, Vec<2>(0.1, 0.1), 0);
  fill_disc(P, m, h, 2, Vec<2>(0.8, 0.8), 0.2, 1.0, Vec<2>(-0.1, -0.1), 1);
  SolverSettings<2> st;
  st.scheme = StressScheme::Averaged;
  st.dt = 0.001;
  st.hyperelastic = true;
  ExplicitSolver<2> solver(grid2(h, 20, 20), P, {m}, st, 1);
  const double ke_before = solver.totals().kinetic_energy;
  double peak = 0.0, worst_gap = 0.0, worst_comp = 0.0, min_stored = 0.0;
  for (int s = 0; s <= 3000; ++s) {
    if (s % 100 == 0) {
      const auto [law, comp] = stored_from_state(P, m);
      const double incr = solver.energy().strain_energy, ke = solver.totals().kinetic_energy;
      if (s % 250 == 0)
        std::printf(
            "t %.2f  KE %.5f  stored: accumulated %.5f, energy of the law at F %.5f, sigma:C^-1:sigma/2 "
            "%.5f\n",
            solver.time(), ke, incr, law, comp);
      peak = std::max(peak, law);
      worst_gap = std::max(worst_gap, std::abs(incr - law));
      worst_comp = std::max(worst_comp, std::abs(incr - comp));
      min_stored = std::min(min_stored, incr);
    }
    if (s < 3000) {
      ASSERT_TRUE(solver.step().ok);
    }
  }
  const double ke_after = solver.totals().kinetic_energy;
  std::printf(
      "KE before %.5f, after the rebound %.5f (%+.2f %%); accumulated vs recomputed stored energy: "
      "largest gap %.2e J (%.2f %% of the peak %.4f J); against sigma:C^-1:sigma/2 %.2e J (%.2f %%)\n",
      ke_before, ke_after, 100 * (ke_after / ke_before - 1), worst_gap, 100 * worst_gap / peak, peak,
      worst_comp, 100 * worst_comp / peak);
  EXPECT_LE(ke_after, ke_before);
  EXPECT_GE(min_stored, 0.0);
  EXPECT_LT(worst_gap, 0.01 * peak);
}
