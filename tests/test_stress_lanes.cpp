// The 3D stress update of a block of eight points in lanes (solver/stress_lanes_3d.hpp,
// material/mohr_coulomb/lanes.hpp) followed, as in the stress phase, by the scalar update of the
// lanes it leaves, gives what the scalar update update_point_stress<3> gives point by point: the
// stress, F, Fe, every state field, -V sigma for the force scatter, the stored and dissipated
// work and the first unsound point, to round-off (1e-12 relative), on random 3D states within and
// beyond yield, for every model, with lanes left out by the point selection. The lanes must
// carry most points, elastic and plastic alike, or the test fails: a lanes path that did
// nothing would pass the comparison.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <random>

#include "model_cases.hpp"
#include "solver/stress_lanes_3d.hpp"

using namespace skred;

namespace {

constexpr double kPa = 1e3;
constexpr double kRel = 1e-12;

// Every model; those whose plastic points the lanes leave to the scalar update (von Mises, a
// tension cut-off) and the hyperelastic law, which stays scalar, are expected there.
struct Case {
  const char* name;
  Material m;
  bool lanes_expected;  // elastic and plastic points both in lanes
};
std::vector<Case> cases() {
  std::vector<Case> out;
  for (const test::NamedModel& n : test::model_cases())
    out.push_back(
        {n.name, n.m, n.m.model != Model::VonMises && !n.m.mohr_coulomb_constants.has_tension_cutoff()});
  Material hyper = test::model_base(Model::LinearElastic);
  hyper.hyperelastic = true;
  hyper.prepare();
  out.push_back({"hyperelastic", hyper, false});
  return out;
}

// Eight points with random stresses (principal values in [-150, 50] kPa, random frame), F, Fe
// and state, and random velocity gradients (dt grad v up to 1e-3, or 2e-2 in every third block).
struct Block {
  Particles<3> P;
  Mat3 m[8];
};
Block random_block(std::mt19937& rng, int index) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Block b;
  Particles<3>& P = b.P;
  P.volume0.resize(8);
  P.material.assign(8, 0);
  P.F.resize(8);
  P.Fe.resize(8);
  P.stress.resize(8);
  P.state.resize(8);
  const double amp = index % 3 == 0 ? 20.0 : 1.0;
  for (int l = 0; l < 8; ++l) {
    const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    const Mat3 R = q.toRotationMatrix();
    const Vec3 values(100 * kPa * u(rng) - 50 * kPa, 100 * kPa * u(rng) - 50 * kPa,
                      100 * kPa * u(rng) - 50 * kPa);
    P.stress[l] = to_voigt(R * values.asDiagonal() * R.transpose());
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        P.F[l](i, j) = (i == j) + 0.3 * u(rng);
        P.Fe[l](i, j) = (i == j) + 0.1 * u(rng);
        b.m[l](i, j) = amp * u(rng);
      }
    P.state[l].plastic_shear_strain = 0.02 * (1 + u(rng));
    P.state[l].plastic_volume_strain = 0.01 * u(rng);
    P.state[l].volume_strain = 0.0124 + 0.01 * u(rng);
    P.state[l].yielding = (index + l) % 2;
    P.volume0[l] = 0.01 * (1.5 + u(rng));
  }
  return b;
}

double rel(double a, double b, double scale) { return std::abs(a - b) / scale; }

}  // namespace

TEST(StressLanes, BlockUpdateEqualsThePointUpdateOnRandomStates) {
  std::mt19937 rng(2027);
  const double dt = 1e-3;
  for (const Case& c : cases()) {
    const std::vector<Material> mats{c.m};
    int in_lanes = 0, plastic_in_lanes = 0, total = 0;
    double worst = 0;
    const int blocks = 300;
    for (int k = 0; k < blocks; ++k) {
      Block ref = random_block(rng, k), lan = ref;
      const unsigned selected = k % 5 == 4 ? 0x5bu : 0xffu;  // some blocks leave points out
      auto sel = [&](long p) { return ((selected >> p) & 1u) != 0u; };
      if (k == 7) ref.m[3] = lan.m[3] = Mat3::Identity() * -2000.0;  // det dF < 0: an unsound point
      // the reference: the scalar update point by point
      const StressArrays<3> SR(ref.P, mats);
      double work_r = 0, diss_r = 0;
      long bad_r = LONG_MAX;
      for (long p = 0; p < 8; ++p) {
        if (!sel(p)) continue;
        const auto r = SR.update_booked(p, ref.m[p], dt, work_r, diss_r, bad_r);
        ref.m[p] = -r.volume * sym_block<3>(SR.stress[p]);
      }
      // the stress phase's way: the lanes, then the scalar update of the rest
      StressArrays<3> SL(lan.P, mats);
      double det_f[8];
      std::fill(det_f, det_f + 8, -7.0);
      SL.det_f = det_f;
      double work_l = 0, diss_l = 0;
      long bad_l = LONG_MAX;
      const unsigned done = lanes3d::update_block(SL, 0, sel, lan.m, dt, work_l, diss_l, bad_l);
      EXPECT_EQ(done & ~selected, 0u) << c.name << " block " << k;
      // the lanes' det F, for the move phase's GIMP sizes, is Eigen's of the new F to the bit;
      // the lanes they leave to the scalar update are not written
      for (int l = 0; l < 8; ++l) {
        const double want = (done >> l) & 1u ? lan.P.F[l].determinant() : -7.0;
        EXPECT_EQ(std::memcmp(&det_f[l], &want, sizeof(double)), 0)
            << c.name << " block " << k << " lane " << l;
      }
      for (long p = 0; p < 8; ++p) {
        if (!sel(p) || ((done >> p) & 1u)) continue;
        const auto r = SL.update_booked(p, lan.m[p], dt, work_l, diss_l, bad_l);
        lan.m[p] = -r.volume * sym_block<3>(SL.stress[p]);
      }
      for (int l = 0; l < 8; ++l) {
        total += sel(l);
        in_lanes += (done >> l) & 1u;
        plastic_in_lanes += c.m.plastic() && ((done >> l) & 1u) && lan.P.state[l].yielding;
      }
      EXPECT_EQ(bad_l, bad_r) << c.name << " block " << k;
      const double ss = 200 * kPa;
      double e = 0;
      for (int l = 0; l < 8; ++l) {
        if (k == 7 && l == 3) continue;  // (the unsound point's numbers are not compared)
        const Particles<3>&A = lan.P, &B = ref.P;
        for (int i = 0; i < 6; ++i) e = std::max(e, rel(A.stress[l][i], B.stress[l][i], ss));
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            e = std::max({e, rel(A.F[l](i, j), B.F[l](i, j), 1.0), rel(A.Fe[l](i, j), B.Fe[l](i, j), 1.0),
                          rel(lan.m[l](i, j), ref.m[l](i, j), ss * 0.05)});
        const double gs = 0.05;  // the strains' scale: dt |grad v| up to 2e-2
        e = std::max({e, rel(A.state[l].plastic_shear_strain, B.state[l].plastic_shear_strain, gs),
                      rel(A.state[l].plastic_volume_strain, B.state[l].plastic_volume_strain, gs),
                      rel(A.state[l].volume_strain, B.state[l].volume_strain, gs)});
        EXPECT_EQ(A.state[l].yielding, B.state[l].yielding) << c.name << " block " << k << " lane " << l;
      }
      if (k != 7) {
        const double ws = 8 * 0.025 * ss * 0.05;  // points x V x |sigma| x |d_eps|
        e = std::max({e, rel(work_l, work_r, ws), rel(diss_l, diss_r, ws)});
      }
      EXPECT_LE(e, kRel) << c.name << " block " << k;
      worst = std::max(worst, e);
    }
    std::printf("  %-32s %4d of %d points in lanes (%d plastic); max rel. diff %.1e\n", c.name, in_lanes,
                total, plastic_in_lanes, worst);
    if (c.lanes_expected) {
      EXPECT_GE(in_lanes, total / 2) << c.name;
      if (c.m.plastic()) {
        EXPECT_GE(plastic_in_lanes, total / 10) << c.name;
      }
    } else if (!c.m.plastic() || c.m.model == Model::VonMises) {
      EXPECT_EQ(in_lanes, 0) << c.name;
    }
  }
}
