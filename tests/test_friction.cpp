// The frictional wall (Thesis eq. 5.8-5.11, src/solver/coulomb_friction.hpp) and its energy
// bookkeeping. R4's horizontal variant: an elastic block thrown at v0 along a base of
// friction mu stops after v0^2 / (2 mu g) at t = v0 / (mu g), and its kinetic energy goes
// into friction work (plus a little stored energy and transfer dissipation), for every
// velocity transfer and two cell sizes (the 2.5 mm cell is in scripts/friction_block.sh).
#include <gtest/gtest.h>

#include <cstdlib>

#include "solver/boundary.hpp"
#include "solver/coulomb_friction.hpp"
#include "support.hpp"

using namespace skred;
using namespace skred::test;

namespace {

constexpr double g = 9.81;

TEST(CoulombFriction, SticksSlipsAndSeparatesWithoutCreatingEnergy) {
  const Vec<2> n(0.0, -1.0);  // a floor: outward normal points down
  // Separation: moving away from the floor, nothing changes.
  EXPECT_EQ(coulomb_contact<2>(Vec<2>(1.0, 0.5), n, 0.5), Vec<2>(1.0, 0.5));
  // Stick: the friction needed to stop 0.1 is within mu times the normal 1.0.
  EXPECT_EQ(coulomb_contact<2>(Vec<2>(0.1, -1.0), n, 0.5), Vec<2>(0.0, 0.0));
  // Slip: full friction 0.5 x 1.0 removed from a slip of 2, against its direction.
  const Vec<2> v = coulomb_contact<2>(Vec<2>(-2.0, -1.0), n, 0.5);
  EXPECT_NEAR(v[0], -1.5, 1e-15);
  EXPECT_EQ(v[1], 0.0);
  // Never more kinetic energy than the trial: random trials, normals and coefficients.
  std::srand(1);
  auto r = [] { return 2.0 * std::rand() / RAND_MAX - 1.0; };
  for (int k = 0; k < 10000; ++k) {
    const Vec<3> vt(r(), r(), r());
    const Vec<3> nn = Vec<3>(r(), r(), r()).normalized();
    const Vec<3> out = coulomb_contact<3>(vt, nn, 2.0 * std::abs(r()));
    EXPECT_LE(out.squaredNorm(), vt.squaredNorm() * (1 + 1e-15));
    EXPECT_LE(out.dot(nn), std::max(0.0, vt.dot(nn)) + 1e-15);  // no motion into the wall
  }
}

struct Throw {
  double stop_distance = 0, stop_time = 0, ke0 = 0, ke_end = 0, friction = 0, stored = 0, transfer = 0,
         gravity = 0, min_step_friction = 0;
  RuleWork rules;  // what the wall rules took, step by step
};

// An 80 mm x 40 mm elastic block (2 x 2 points per cell) thrown at v0 along a frictional floor,
// from its static stress (no elastic wave), for `time` seconds; XPIC once per `period` crossing
// times h/c if it is set (solver.xpic_period).
Throw throw_block(double h, VelocityTransfer transfer, StressScheme scheme, double mu, double v0, double time,
                  double period = 0.0) {
  const Material m = elastic(2000.0, 1e7, 0.0);
  const double H = 0.04, L = 0.08;
  Particles<2> P;
  fill_rectangle(P, m, h, 2, h, 0.0, h + L, H, Vec<2>(v0, 0.0));
  for (std::size_t p = 0; p < P.size(); ++p) P.stress[p][1] = -m.density * g * (H - P.x[p][1]);
  SolverSettings<2> st;
  st.interpolation = Interpolation::Gimp;
  st.scheme = scheme;
  st.velocity_transfer = transfer;
  st.xpic_period = period * h / m.wave_speed();
  st.dt = 0.2 * h / m.wave_speed();
  st.gravity = Vec<2>(0.0, -g);
  st.boundaries = {side(BoundaryKind::Free), side(BoundaryKind::Free), side(BoundaryKind::Friction, mu),
                   side(BoundaryKind::Free)};
  const int nx = static_cast<int>(std::lround(0.25 / h)), ny = static_cast<int>(std::lround(0.06 / h));
  ExplicitSolver<2> solver(grid2(h, nx, ny), P, {m}, st, 1);
  Throw r;
  r.ke0 = solver.totals().kinetic_energy;
  r.min_step_friction = INFINITY;
  const long steps = std::lround(time / st.dt);
  double last_v = v0, last_t = 0.0;
  for (long s = 0; s < steps; ++s) {
    const auto status = solver.step();
    EXPECT_TRUE(status.ok) << status.reason;
    if (!status.ok) break;
    // the walls' step sum before a negative one is dropped (WallEnergy::work_sum)
    r.min_step_friction = std::min(r.min_step_friction, solver.wall_step().work_sum);
    r.rules.add(solver);
    const auto t = solver.totals();
    const double v = t.momentum[0] / t.mass;
    if (r.stop_time == 0.0 && v <= 1e-3 * v0)  // first time the block is (nearly) at rest
      r.stop_time = last_t + (solver.time() - last_t) * (last_v - 1e-3 * v0) / (last_v - v);
    last_v = v;
    last_t = solver.time();
  }
  for (std::size_t p = 0; p < P.size(); ++p) r.stop_distance += P.x[p][0] - P.x_ref[p][0];
  r.stop_distance /= P.size();
  const auto& e = solver.energy();
  r.ke_end = solver.totals().kinetic_energy;
  r.friction = e.friction_work;
  r.stored = e.strain_energy;
  r.transfer = e.transfer_dissipation;
  r.gravity = e.gravity_work;
  return r;
}

void check_throw(double h, VelocityTransfer transfer, StressScheme scheme, double period = 0.0) {
  const double v0 = 1.0, mu = 0.466;
  const double stop = v0 * v0 / (2 * mu * g), t_stop = v0 / (mu * g);  // 0.1094 m, 0.2187 s
  const Throw r = throw_block(h, transfer, scheme, mu, v0, 1.25 * t_stop, period);
  const double balance = r.ke_end + r.friction + r.stored + r.transfer - r.gravity;
  std::printf(
      "h %.1f mm %s%s %s: stops after %.5f m (exact %.5f, %+.2f %%) at %.4f s (exact %.4f, "
      "%+.2f %%); KE0 %.5f J/m = friction %.5f + stored %.2e + transfer %.2e + KE %.1e - "
      "W_g %.1e (%+.3f %%); friction + stored %+.3f %%; smallest step friction work %.1e (rule %.1e), "
      "dropped %.1e\n",
      1e3 * h, to_string(transfer), period > 0 ? " per 2 h/c" : "", to_string(scheme), r.stop_distance, stop,
      100 * (r.stop_distance - stop) / stop, r.stop_time, t_stop, 100 * (r.stop_time - t_stop) / t_stop,
      r.ke0, r.friction, r.stored, r.transfer, r.ke_end, r.gravity, 100 * (balance - r.ke0) / r.ke0,
      100 * (r.friction + r.stored - r.ke0) / r.ke0, r.min_step_friction, r.rules.min_rule, r.rules.dropped);
  EXPECT_NEAR(r.stop_distance, stop, 0.02 * stop);
  EXPECT_GE(r.rules.min_rule, 0.0);  // the wall rules take energy from the trial velocities at every step
  // The booked work (the kinetic energy change less the forces' work over the mean velocity)
  // dips below zero on some steps by O(dt^2) (smallest -9e-7 J/m here); those steps book nothing,
  // which moves the balance by under 1e-4 of the thrown energy (at most 2.6e-4 J/m of 3.2).
  EXPECT_LT(r.rules.dropped, 1e-4 * r.ke0);
  if (transfer == VelocityTransfer::Flip) return;  // see FlipChattersAtTheWall
  EXPECT_NEAR(r.stop_time, t_stop, 0.02 * t_stop);
  EXPECT_NEAR(r.friction + r.stored, r.ke0, 0.01 * r.ke0);
  EXPECT_NEAR(balance, r.ke0, 0.01 * r.ke0);
}

}  // namespace

TEST(FrictionalBlock, ThrownBlockStopsAtTheAnalyticDistanceAndTime) {
  const char* cells = std::getenv("SKRED_FRICTION_CELLS");  // scripts/friction_block.sh: 0.0025
  const std::vector<double> sizes =
      cells ? std::vector<double>{std::atof(cells)} : std::vector<double>{0.01, 0.005};
  for (double h : sizes) {
    for (VelocityTransfer t : {VelocityTransfer::Flip, VelocityTransfer::Xpic, VelocityTransfer::Apic})
      check_throw(h, t, StressScheme::Averaged);
    check_throw(h, VelocityTransfer::Xpic, StressScheme::Averaged, 2.0);  // XPIC once per 2 h/c
  }
}

TEST(FrictionalBlock, ThrownBlockStopsWithEveryScheme) {
  for (StressScheme s : {StressScheme::USF, StressScheme::USL}) check_throw(0.01, VelocityTransfer::Xpic, s);
}

// The affine FLIP (Fei et al. 2021): FLIP's update with APIC's map stops the block where and when
// it should (measured -0.05 / +0.13 % at 10 mm, -0.09 / +0.69 % at 5 mm). It keeps part of FLIP's
// wall chatter: at 5 mm the block is lifted a little and friction + stored energy falls 1.7 %
// short of the thrown energy (0.8 % at 10 mm; docs/method.md, "The affine FLIP").
TEST(FrictionalBlock, AffineFlipStopsAtTheAnalyticDistanceAndTime) {
  const double v0 = 1.0, mu = 0.466;
  const double stop = v0 * v0 / (2 * mu * g), t_stop = v0 / (mu * g);
  const char* cells = std::getenv("SKRED_FRICTION_CELLS");  // scripts/friction_block.sh: 0.0025
  for (double h : cells ? std::vector<double>{std::atof(cells)} : std::vector<double>{0.01, 0.005}) {
    const Throw r = throw_block(h, VelocityTransfer::Aflip, StressScheme::Averaged, mu, v0, 1.25 * t_stop);
    std::printf("h %.1f mm aflip: stops after %+.2f %% at %+.2f %%; friction + stored %+.3f %% of KE0\n",
                1e3 * h, 100 * (r.stop_distance - stop) / stop, 100 * (r.stop_time - t_stop) / t_stop,
                100 * (r.friction + r.stored - r.ke0) / r.ke0);
    EXPECT_NEAR(r.stop_distance, stop, 0.02 * stop);
    EXPECT_NEAR(r.stop_time, t_stop, 0.02 * t_stop);
    EXPECT_GE(r.rules.min_rule, 0.0);
    EXPECT_LT(r.rules.dropped, 1e-4 * r.ke0);
    if (h >= 0.01) {
      EXPECT_NEAR(r.friction + r.stored, r.ke0, 0.01 * r.ke0);
    }
  }
}

// Pure FLIP (Thesis eq. 2.56) stops the block at the right distance, but the points next to
// the wall keep velocities the wall nodes do not have (FLIP's null space): the wall nodes'
// velocity jumps every step, the block creeps to a stop 5-8 % late and part of its kinetic
// energy goes into lifting it (the balance still closes, within 0.5 %). Recorded here; XPIC
// and APIC remove it (ThrownBlockStopsAtTheAnalyticDistanceAndTime).
TEST(FrictionalBlock, FlipChattersAtTheWall) {
  const double v0 = 1.0, mu = 0.466, t_stop = v0 / (mu * g);
  const Throw r = throw_block(0.01, VelocityTransfer::Flip, StressScheme::Averaged, mu, v0, 1.25 * t_stop);
  const Throw x = throw_block(0.01, VelocityTransfer::Xpic, StressScheme::Averaged, mu, v0, 1.25 * t_stop);
  EXPECT_GT(r.stop_time, 1.02 * t_stop);
  EXPECT_LT(r.gravity, 100 * x.gravity);  // lifted: negative work of gravity
  EXPECT_NEAR(r.ke_end + r.friction + r.stored + r.transfer - r.gravity, r.ke0, 0.01 * r.ke0);
  // The lift comes from the friction (docs/method.md, "How FLIP lifts the block"): on the same
  // wall without it the block translates exactly, and nothing lifts it.
  const Throw smooth = throw_block(0.01, VelocityTransfer::Flip, StressScheme::Averaged, 0.0, v0, 0.1);
  EXPECT_LT(std::abs(smooth.gravity), 1e-12 * smooth.ke0);
  EXPECT_NEAR(smooth.ke_end, smooth.ke0, 1e-12 * smooth.ke0);
  EXPECT_GT(-r.gravity, 0.01 * r.ke0);  // with it, 1.6 % of the thrown energy went into lift
}

// The walks over the boundary nodes visit only those inside the box of nodes the points reach
// (Boundaries::constrain_velocity, constrain_end_of_step): inside it they do what the walk over
// the whole grid does, outside it they leave every node as it was.
TEST(Boundaries, WalksInsideTheBoxDoWhatTheWholeGridWalkDoesThere) {
  GridGeometry<3> g;
  g.h = 0.5;
  g.cells = {7, 5, 4};
  std::array<BoundarySide, 6> sides{};
  sides[0] = {BoundaryKind::Fixed, 0.0};
  sides[1] = {BoundaryKind::Roller, 0.0};
  sides[2] = {BoundaryKind::Friction, 0.5};
  sides[4] = {BoundaryKind::Roller, 0.0};
  sides[5] = {BoundaryKind::Friction, 0.3};
  const Boundaries<3> walls(g, sides);
  NodeBox<3> all, box;
  for (int d = 0; d < 3; ++d) all.hi[d] = g.nodes(d) - 1;
  box.lo = {1, 1, 2};
  box.hi = {4, 6, 6};
  const auto inside = [&](std::size_t i) {
    const auto ij = g.unflatten(i);
    for (int d = 0; d < 3; ++d)
      if (ij[d] < box.lo[d] || ij[d] > box.hi[d]) return false;
    return true;
  };
  std::srand(7);
  const auto random = [] { return 2.0 * std::rand() / RAND_MAX - 1.0; };
  const std::size_t n = g.node_count();
  GridArray<Vec<3>> v(n);
  for (auto& vi : v) vi = Vec<3>(random(), random(), random());
  GridArray<Vec<3>> in_box = v, whole = v;
  walls.constrain_velocity(in_box, box);
  walls.constrain_velocity(whole, all);
  int constrained = 0;
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(in_box[i], inside(i) ? whole[i] : v[i]) << "node " << i;
    constrained += inside(i) && whole[i] != v[i];
  }
  EXPECT_GT(constrained, 20);  // the box holds nodes of every kind of wall

  // The end of the step, with mass only inside the box (as the points put it there).
  GridFields<3> f;
  f.resize(n, false, false);
  for (std::size_t i = 0; i < n; ++i) {
    if (!inside(i)) continue;
    f.mass[i] = 1.0 + random();
    f.momentum[i] = f.mass[i] * Vec<3>(random(), random(), random());
    f.velocity[i] = f.momentum[i] / f.mass[i];
    f.acceleration[i] = Vec<3>(random(), random(), random());
  }
  walls.constrain_velocity(f.velocity, all);
  GridFields<3> f_box = f;
  const WallEnergy e_all = walls.constrain_end_of_step(f, 0.01, all);
  const WallEnergy e_box = walls.constrain_end_of_step(f_box, 0.01, box);
  EXPECT_GT(e_all.work, 0.0);
  EXPECT_EQ(e_box.work, e_all.work);
  EXPECT_EQ(e_box.update_loss_end, e_all.update_loss_end);
  EXPECT_EQ(e_box.update_loss_change, e_all.update_loss_change);
  EXPECT_EQ(e_box.stopping, e_all.stopping);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(f_box.acceleration[i], f.acceleration[i]) << "node " << i;
    EXPECT_EQ(f_box.velocity_move[i], f.velocity_move[i]) << "node " << i;
  }
}
