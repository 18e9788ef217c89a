// The velocity transfers (src/solver/velocity_transfer.hpp): FLIP (Thesis eq. 2.56), XPIC(m)
// (Hammerquist & Nairn 2017), APIC (Jiang et al. 2015) and the affine FLIP (Fei et al. 2021),
// with every scheme: momentum to
// round-off, the R3 discs' energy with the transfer's dissipation booked, and the soil column
// of Thesis §5.1 coming to rest.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include <filesystem>

#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "support.hpp"
#include "temp_dir.hpp"
#include "text_run.hpp"

namespace fs = std::filesystem;
using namespace skred;
using namespace skred::test;

namespace {

struct DiscEnergy {
  double e0 = 0, e_end = 0, transfer = 0, max_momentum = 0, mass = 0, ke_before = 0, ke_after = 0;
  double max_momentum_change = 0;  // |P(t) - P(0)|, largest over the run
};

// R3 (tests/test_discs.cpp): colliding elastic discs, 3000 steps of 1 ms; XPIC once per
// `xpic_period` seconds if it is set. `v0` is disc 0's velocity (R3's, (0.1, 0.1), makes the two
// discs mirror images and the total momentum zero by symmetry alone).
DiscEnergy discs(VelocityTransfer t, StressScheme scheme, int steps = 3000, double xpic_period = 0.0,
                 Vec<2> v0 = Vec<2>(0.1, 0.1)) {
  const Material m = elastic(1000.0, 1000.0, 0.3);
  const double h = 0.05;
  Particles<2> P;
  fill_disc(P, m, h, 2, Vec<2>(0.2, 0.2), 0.2, 1.0, v0, 0);
  fill_disc(P, m, h, 2, Vec<2>(0.8, 0.8), 0.2, 1.0, Vec<2>(-0.1, -0.1), 1);
  SolverSettings<2> st;
  st.scheme = scheme;
  st.velocity_transfer = t;
  st.xpic_period = xpic_period;
  st.dt = 0.001;
  st.hyperelastic = true;  // R3's 25 % squeeze: the law that returns the energy of F
  ExplicitSolver<2> solver(grid2(h, 20, 20), P, {m}, st, 2);
  DiscEnergy r;
  r.mass = solver.totals().mass;
  r.e0 = r.ke_before = solver.totals().kinetic_energy;
  const Vec<2> p0 = solver.totals().momentum;
  for (int s = 0; s < steps; ++s) {
    EXPECT_TRUE(solver.step().ok);
    const auto tot = solver.totals();
    r.max_momentum = std::max(r.max_momentum, tot.momentum.norm());
    r.max_momentum_change = std::max(r.max_momentum_change, (tot.momentum - p0).norm());
  }
  r.ke_after = solver.totals().kinetic_energy;
  r.e_end = r.ke_after + solver.energy().strain_energy;
  r.transfer = solver.energy().transfer_dissipation;
  return r;
}

// An elastic block, free in space, whose points start with a short-wave velocity field (wavelength
// 4 h, omega dt = 0.58): the PIC share or XPIC damps it over the run, a few hundred steps, while
// it vibrates. Returns the balance kinetic + strain + transfer dissipation - initial kinetic energy,
// over the initial kinetic energy, after `steps` steps (2 s).
double vibrating_block_balance(VelocityTransfer t, double pic_fraction, StressScheme scheme,
                               int steps = 200) {
  Particles<2> P;
  const Material m = vibrating_block(P);  // c_p = 3.7 m/s: c dt / h = 0.37
  SolverSettings<2> st;
  st.scheme = scheme;
  st.velocity_transfer = t;
  st.pic_fraction = pic_fraction;
  st.dt = 0.01;
  ExplicitSolver<2> solver(grid2(0.1, 20, 20), P, {m}, st, 1);
  const double ke0 = solver.totals().kinetic_energy;
  for (int s = 0; s < steps; ++s) EXPECT_TRUE(solver.step().ok);
  const EnergyTotals& e = solver.energy();
  return (solver.totals().kinetic_energy + e.strain_energy + e.transfer_dissipation - ke0) / ke0;
}

}  // namespace

TEST(VelocityTransfer, VibratingBlockBalanceWithThePicShareAndXpicLossBooked) {
  // The loss of the PIC share and of XPIC is what they take from the scheme's energy
  // (particle_velocity). Booked as the kinetic energy difference 1/2 m_p (|v_p^FLIP|^2 - |v_p^{k+1}|^2)
  // it missed this balance (PIC share 1 / XPIC) by -5.4 / -4.5 % (USF), -2.0 / -3.1 % (USL) and
  // -8.4 / -8.1 % (averaged); now 0.19 % at most (docs/studies/2026-11-25-pic-share-and-xpic-booked-loss.md).
  for (StressScheme s : {StressScheme::USF, StressScheme::USL, StressScheme::Averaged}) {
    const double pic = vibrating_block_balance(VelocityTransfer::Flip, 1.0, s);
    const double xpic = vibrating_block_balance(VelocityTransfer::Xpic, 0.0, s);
    std::printf("vibrating block, %s: balance with the PIC share 1: %+.3f %%, XPIC: %+.3f %%\n", to_string(s),
                100 * pic, 100 * xpic);
    EXPECT_LT(std::abs(pic), 0.005) << to_string(s);
    EXPECT_LT(std::abs(xpic), 0.005) << to_string(s);
  }
}

// R3's discs are mirror images of each other through the square's centre, so their total
// momentum stays zero by symmetry whatever a transfer does to it. Here disc 0 comes at 1.5
// times disc 1's speed: the total momentum, M/2 (0.05, 0.05), must stay as it is (every map and
// update sums to it: partition of unity, and sum_i N_ip (x_i - x_p) = 0 for APIC's affine part).
TEST(VelocityTransfer, MomentumIsConservedToRoundOffByEveryTransferAndScheme) {
  for (VelocityTransfer t :
       {VelocityTransfer::Flip, VelocityTransfer::Xpic, VelocityTransfer::Apic, VelocityTransfer::Aflip})
    for (StressScheme s : {StressScheme::USF, StressScheme::USL, StressScheme::Averaged}) {
      // through the first contact (t = 1.27 s) and the rebound
      const DiscEnergy r = discs(t, s, 2000, 0.0, Vec<2>(0.15, 0.15));
      EXPECT_GT(r.max_momentum, 0.02 * r.mass);
      EXPECT_LT(r.max_momentum_change, 1e-12 * r.mass * 0.1) << to_string(t) << " " << to_string(s);
    }
}

TEST(VelocityTransfer, DiscEnergyWithTheTransferDissipationBooked) {
  // Averaged scheme (Thesis fig. 4.6). KE + strain energy drifts by what the transfer
  // dissipates; with that booked the balance holds.
  // The last run: XPIC once per 2 h/c (c = 1.16 m/s, h = 0.05 m: every 86 steps; periodic_xpic).
  const double periods[] = {0.0, 0.0, 0.0, 2.0 * 0.05 / std::sqrt(1000.0 * 0.7 / (1.3 * 0.4 * 1000.0)), 0.0};
  const VelocityTransfer transfers[] = {VelocityTransfer::Flip, VelocityTransfer::Xpic,
                                        VelocityTransfer::Apic, VelocityTransfer::Xpic,
                                        VelocityTransfer::Aflip};
  for (int k = 0; k < 5; ++k) {
    const VelocityTransfer t = transfers[k];
    const DiscEnergy r = discs(t, StressScheme::Averaged, 3000, periods[k]);
    const double drift = (r.e_end - r.e0) / r.e0;
    const double booked = (r.e_end + r.transfer - r.e0) / r.e0;
    std::printf(
        "R3 discs, %s%s: KE + strain energy %+.3f %%, transfer dissipation %.3f %%, balance "
        "%+.3f %%; KE after the rebound %.4f vs %.4f before\n",
        to_string(t), k == 3 ? " per 2 h/c" : "", 100 * drift, 100 * r.transfer / r.e0, 100 * booked,
        r.ke_after, r.ke_before);
    // APIC's kinetic energy includes its affine velocity's, 1/2 m_p sum_i N_ip |C_p (x_i - x_p)|^2,
    // and its booked loss is against that (docs/method.md, "Velocity transfers").
    EXPECT_LT(std::abs(booked), 0.01);
    EXPECT_LE(r.ke_after, r.ke_before);  // no energy from nowhere through the rebound
  }
}

// The affine FLIP is FLIP's update of v_p (eq. 2.56) with APIC's affine velocity and map: from
// points with no affine velocity yet, one step gives FLIP's velocities and APIC's C_p to the bit;
// the next step's map carries C_p, so the second step is neither.
TEST(VelocityTransfer, AffineFlipTakesFlipsVelocityAndApicsAffineVelocity) {
  const auto run = [](VelocityTransfer t, int steps) {
    const Material m = elastic(1000.0, 1000.0, 0.3);
    auto P = std::make_unique<Particles<2>>();
    fill_disc(*P, m, 0.05, 2, Vec<2>(0.2, 0.2), 0.2, 1.0, Vec<2>(0.1, 0.1), 0);
    for (std::size_t p = 0; p < P->size(); ++p)  // a rotation (C_p not zero) and a short wave the grid
      P->v[p] +=
          Vec<2>(-(P->x[p][1] - 0.2) + 0.01 * std::sin(60.0 * P->x[p][0]), P->x[p][0] - 0.2);  // smooths
    SolverSettings<2> st;
    st.velocity_transfer = t;
    st.dt = 0.001;
    ExplicitSolver<2> solver(grid2(0.05, 20, 20), *P, {m}, st, 1);
    for (int s = 0; s < steps; ++s) EXPECT_TRUE(solver.step().ok);
    return P;
  };
  const auto flip = run(VelocityTransfer::Flip, 1), apic = run(VelocityTransfer::Apic, 1),
             aflip = run(VelocityTransfer::Aflip, 1);
  ASSERT_EQ(aflip->affine.size(), aflip->size());
  double largest_c = 0.0;
  std::size_t not_apic = 0;
  for (std::size_t p = 0; p < aflip->size(); ++p) {
    EXPECT_EQ(aflip->v[p], flip->v[p]) << p;
    EXPECT_EQ(aflip->affine[p], apic->affine[p]) << p;
    not_apic += aflip->v[p] != apic->v[p];
    largest_c = std::max(largest_c, aflip->affine[p].norm());
  }
  EXPECT_GT(not_apic, aflip->size() / 2);  // APIC's v_p is the grid's, without the short wave's rest
  EXPECT_GT(largest_c, 1.0);               // the rotation's 1 rad/s
  const auto flip2 = run(VelocityTransfer::Flip, 2), aflip2 = run(VelocityTransfer::Aflip, 2);
  int differ = 0;
  for (std::size_t p = 0; p < aflip2->size(); ++p) differ += aflip2->v[p] != flip2->v[p];
  EXPECT_GT(differ, 0);
}

namespace {

// examples/soil_column.toml (Thesis §5.1) for 3 s with the velocity transfer t (empty: the
// example as it is, XPIC once per 2 h/c, for its 6 s) and, if given,
// the base `wall` in place of its frictional one, on two threads: the run and the last
// series.csv row (total_energy, gravity_work, ...).
using ColumnRun = TextRun;
ColumnRun soil_column(const std::string& t, const std::string& wall = "") {
  std::string text = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml");
  if (!t.empty()) {  // (the example's own transfer: its whole 6 s)
    text.replace(text.find("duration = 6.0"), 14, "duration = 3.0");
    text = with_transfer(text, "velocity_transfer = \"" + t + "\"");
  }
  const std::string friction_base = "y_min = { type = \"friction\", friction = 0.6 }";
  if (!wall.empty()) text.replace(text.find(friction_base), friction_base.size(), "y_min = \"" + wall + "\"");
  return run_text(text, 2);
}

}  // namespace

TEST(VelocityTransfer, SoilColumnComesToRest) {
  // The mean speed of eq. 5.12 against the example's rest speed, 0.005 m/s: the example's own
  // transfer (XPIC once per 2 h/c) and APIC. (FLIP: SoilColumnCollapsesSymmetricallyAndComesToRest.
  // XPIC at every step, with this example's point strain, still creeps at 0.1 m/s at 3 s and
  // rests only at 6 s: "Runout under refinement".)
  for (const char* t : {"", "apic"}) {
    const ColumnRun c = soil_column(t);
    ASSERT_TRUE(c.result.completed) << c.result.message;
    const double balance = c.balance();
    const StageMeasures& m = c.result.stages[0];
    std::printf(
        "soil column, %s: ended by %s at %.2f s, final mean speed %.4f m/s, runout %.2f m, energy "
        "balance %+.2f %% of the gravity work\n",
        *t ? t : "the example's xpic per 2 h/c", m.ended_by.c_str(), m.end_time, m.final_mean_speed, m.runout,
        100 * balance);
    EXPECT_EQ(m.ended_by, "rest") << t;
    // issue 12: closes within 1 % with the transfer's loss (APIC measured +0.88 %). (XPIC at every
    // step misses it by +2.9 % at 3 s, +1.4 % at dt / 2: the step's error on the frictional base,
    // docs/method.md, "The walls' share of the lumped mass's loss".)
    EXPECT_LT(std::abs(balance), 0.01) << t;
  }
}

// The walls' share of the lumped mass's loss (docs/method.md): the soil column on a fixed base
// (each transfer) and on a roller base (XPIC), USF. Without it the balance missed -3.1 % (FLIP),
// -0.8 % (APIC) and -3.0 % (XPIC, roller): the points lost to the walls more kinetic energy than
// the nodes' booked work says.
TEST(VelocityTransfer, ColumnOnFixedAndRollerBasesBooksTheWallsShare) {
  for (const auto& [wall, t] : std::vector<std::pair<std::string, std::string>>{
           {"fixed", "flip"}, {"fixed", "xpic"}, {"fixed", "apic"}, {"fixed", "aflip"}, {"roller", "xpic"}}) {
    const ColumnRun c = soil_column(t, wall);
    ASSERT_TRUE(c.result.completed) << c.result.message;
    std::printf("soil column, %s base, %s: energy balance %+.3f %% of the gravity work (transfer %.3f %%)\n",
                wall.c_str(), t.c_str(), 100 * c.balance(),
                100 * c.row.at("transfer_dissipation") / c.row.at("gravity_work"));
    EXPECT_LT(std::abs(c.balance()), 0.005);  // measured +0.14, -0.01, +0.36, +0.07, -0.16 %
  }
}

TEST(VelocityTransfer, ScenarioKeys) {
  std::string base = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml");
  const auto with = [&](const std::string& keys) {
    return parse_scenario(with_transfer(base, keys), "column.toml");
  };
  const Scenario x = with("velocity_transfer = \"xpic\"\nxpic_order = 3");
  EXPECT_EQ(x.velocity_transfer, VelocityTransfer::Xpic);
  EXPECT_EQ(x.xpic_order, 3);
  EXPECT_EQ(with("velocity_transfer = \"apic\"").velocity_transfer, VelocityTransfer::Apic);
  EXPECT_EQ(with("velocity_transfer = \"aflip\"").velocity_transfer, VelocityTransfer::Aflip);
  EXPECT_ANY_THROW(with("velocity_transfer = \"aflip\"\npic_fraction = 0.1"));
  EXPECT_EQ(solver_settings(with("velocity_transfer = \"apic\"")).velocity_transfer, VelocityTransfer::Apic);
  EXPECT_ANY_THROW(with("velocity_transfer = \"pic\""));
  EXPECT_ANY_THROW(with("velocity_transfer = \"flip\"\nxpic_order = 3"));
  EXPECT_ANY_THROW(with("velocity_transfer = \"apic\"\npic_fraction = 0.1"));
  // APIC (and the affine FLIP, with the same C_p) with the linear kernel or quadrature GIMP is
  // refused (each goes unstable), naming the key
  for (const char* kernel : {"linear", "gimp-quadrature"}) {
    std::string kerneled = base;
    kerneled.replace(kerneled.find("interpolation = \"gimp\""), 22,
                     std::string("interpolation = \"") + kernel + "\"");
    const std::string text = with_transfer(kerneled, "velocity_transfer = \"apic\"");
    const std::string flip = with_transfer(kerneled, "");
    EXPECT_NO_THROW((void)parse_scenario(flip, "column.toml")) << kernel;
    EXPECT_ANY_THROW(
        (void)parse_scenario(with_transfer(kerneled, "velocity_transfer = \"aflip\""), "column.toml"));
    try {
      (void)parse_scenario(text, "column.toml");
      ADD_FAILURE() << "apic with " << kernel << " was accepted";
    } catch (const ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find("solver.velocity_transfer"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(kernel), std::string::npos) << e.what();
    }
  }
  // solver.elastic_update: the seeds' incremental update unless asked for the hyperelastic law
  EXPECT_FALSE(solver_settings(with("")).hyperelastic);
  EXPECT_TRUE(solver_settings(with("elastic_update = \"hyperelastic\"")).hyperelastic);
  EXPECT_ANY_THROW(with("elastic_update = \"hyper\""));
}

// solver.velocity_transfer and volumetric_strain = "auto" (the defaults; docs/method.md, "The
// defaults"): a scenario whose deformable bodies can yield (the Mohr-Coulomb soil column) gets
// exactly the settings of XPIC(2) once per 2 h/c with the cell-averaged volumetric strain; an
// elastic one (R3's discs) FLIP with each point's own strain; a key of one transfer alone picks it.
TEST(VelocityTransfer, AutoPicksTheTransferByTheMaterials) {
  std::string column = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml");
  const std::string point = "volumetric_strain = \"point\"";
  column.replace(column.find(point), point.size(), "");
  const auto with = [&](const std::string& keys) {
    return solver_settings(parse_scenario(with_transfer(column, keys), "column.toml"));
  };
  const SolverSettings a = with(""), x = with(kExampleTransfer + "\nvolumetric_strain = \"cell-average\"");
  EXPECT_EQ(a.velocity_transfer, VelocityTransfer::Xpic);
  EXPECT_GT(a.xpic_period, 0.0);
  EXPECT_EQ(a.xpic_period, x.xpic_period);  // 2 h/c, in seconds
  EXPECT_EQ(a.xpic_order, 2);
  EXPECT_TRUE(a.volumetric_averaging);
  EXPECT_EQ(a.pic_fraction, 0.0);
  EXPECT_TRUE(parse_scenario(with_transfer(column, ""), "column.toml").transfer_by_default);
  // one transfer's key alone picks that transfer; an explicit choice keeps its own defaults
  EXPECT_EQ(with("pic_fraction = 0.1").velocity_transfer, VelocityTransfer::Flip);
  EXPECT_EQ(with("xpic_order = 3").xpic_order, 3);
  EXPECT_EQ(with("xpic_order = 3").xpic_period, x.xpic_period);
  EXPECT_EQ(with("velocity_transfer = \"xpic\"").xpic_period, 0.0);
  EXPECT_FALSE(with("volumetric_strain = \"point\"").volumetric_averaging);
  EXPECT_EQ(with("velocity_transfer = \"auto\"").velocity_transfer, VelocityTransfer::Xpic);

  const Scenario discs = parse_scenario(
      read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/colliding_discs.toml"), "discs.toml");
  const SolverSettings e = solver_settings(discs);
  EXPECT_TRUE(discs.transfer_by_default);
  EXPECT_EQ(e.velocity_transfer, VelocityTransfer::Flip);
  EXPECT_EQ(e.pic_fraction, 0.0);
  EXPECT_FALSE(e.volumetric_averaging);
}

// End to end: the soil column (1 s of it) naming no transfer runs as the one naming XPIC(2) once
// per 2 h/c with the cell-averaged strain, to the last bit of series.csv's last row.
TEST(VelocityTransfer, AutoRunsAsTheSlideDefaultsNamed) {
  std::string column = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml");
  column.replace(column.find("duration = 6.0"), 14, "duration = 1.0");
  std::string unset = with_transfer(column, "");
  const std::string point = "volumetric_strain = \"point\"";
  unset.replace(unset.find(point), point.size(), "");
  const TextRun a = run_text(unset, 1);
  const TextRun x =
      run_text(with_transfer(column, kExampleTransfer + "\nvolumetric_strain = \"cell-average\""), 1);
  ASSERT_TRUE(a.result.completed) << a.result.message;
  ASSERT_FALSE(a.row.empty());
  EXPECT_EQ(a.row, x.row);
  ASSERT_FALSE(a.result.stages.empty());
  EXPECT_EQ(a.result.stages.back().runout, x.result.stages.back().runout);
  EXPECT_GT(a.result.stages.back().runout, 0.0);
}

// skred check tells a user who picks FLIP or the affine FLIP beside a frictional wall what that
// wall does to them (docs/method.md, "How FLIP lifts the block"), and nobody else.
TEST(VelocityTransfer, CheckNotesFlipAtAFrictionalWall) {
  const std::string column = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml");
  const auto noted = [](const std::string& text) {
    return describe(parse_scenario(text, "column.toml")).find("a frictional wall turns part of") !=
           std::string::npos;
  };
  EXPECT_TRUE(noted(with_transfer(column, "velocity_transfer = \"flip\"")));
  EXPECT_TRUE(noted(with_transfer(column, "velocity_transfer = \"aflip\"")));
  EXPECT_FALSE(noted(with_transfer(column, "velocity_transfer = \"flip\"\npic_fraction = 0.05")));
  EXPECT_FALSE(noted(with_transfer(column, "velocity_transfer = \"apic\"")));
  EXPECT_FALSE(noted(column));  // XPIC once per 2 h/c
  const std::string base = "y_min = { type = \"friction\", friction = 0.6 }";
  std::string fixed = with_transfer(column, "velocity_transfer = \"flip\"");
  fixed.replace(fixed.find(base), base.size(), "y_min = \"fixed\"");
  EXPECT_FALSE(noted(fixed));  // no frictional side
}
