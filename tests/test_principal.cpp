// Principal decomposition of the soil models (material/principal.hpp): hand-computed eigen-systems,
// Eigen's own eigensolver, and the closed form on the states where closed forms break; and
// Mohr-Coulomb's eigenvalue-free elastic screen against the accurate principal values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "material/mohr_coulomb.hpp"
#include "material/principal.hpp"

#include "plasticity_reference.hpp"

using namespace skred;
using namespace skred::plasticity_test;

// =============================================================================================
// Principal decomposition

TEST(Principal, PlaneStrainHandComputed) {
  // [[2,1],[1,2]] in plane, zz = 5: eigenvalues 1, 3, 5 with (1,-1,0)/sqrt2, (1,1,0)/sqrt2, e_z.
  Sym3 s;
  s << 2, 2, 5, 1, 0, 0;
  const Principal p = principal_decomposition(s);
  EXPECT_NEAR(p.values[0], 1.0, 1e-15);
  EXPECT_NEAR(p.values[1], 3.0, 1e-15);
  EXPECT_NEAR(p.values[2], 5.0, 1e-15);
  const double r = 1 / std::sqrt(2.0);
  EXPECT_NEAR(std::abs(p.vectors.col(0).dot(Eigen::Vector3d(r, -r, 0))), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(p.vectors.col(1).dot(Eigen::Vector3d(r, r, 0))), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(p.vectors.col(2).dot(Eigen::Vector3d(0, 0, 1))), 1.0, 1e-15);
  // zz in the middle and a yy-dominant in-plane block: [[1, 2], [2, 4]] -> 0, 5; zz = 3.
  s << 1, 4, 3, 2, 0, 0;
  const Principal q = principal_decomposition(s);
  EXPECT_NEAR(q.values[0], 0.0, 1e-15);
  EXPECT_NEAR(q.values[1], 3.0, 1e-15);
  EXPECT_NEAR(q.values[2], 5.0, 1e-14);
  EXPECT_NEAR(std::abs(q.vectors.col(0).dot(Eigen::Vector3d(2, -1, 0) / std::sqrt(5.0))), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(q.vectors.col(1)[2]), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(q.vectors.col(2).dot(Eigen::Vector3d(1, 2, 0) / std::sqrt(5.0))), 1.0, 1e-15);
  // Fully equal: -7 I in plane strain.
  s << -7, -7, -7, 0, 0, 0;
  const Principal h = principal_decomposition(s);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(h.values[i], -7.0);
  EXPECT_NEAR((h.vectors.transpose() * h.vectors - Mat3::Identity()).norm(), 0.0, 1e-15);
}

TEST(Principal, General3DHandComputed) {
  // [[4,1,0],[1,4,1],[0,1,4]]: 4 - sqrt2, 4, 4 + sqrt2 with (1,-sqrt2,1)/2, (1,0,-1)/sqrt2,
  // (1,sqrt2,1)/2.
  Sym3 s;
  s << 4, 4, 4, 1, 1, 0;
  const Principal p = principal_decomposition(s);
  const double r2 = std::sqrt(2.0);
  EXPECT_NEAR(p.values[0], 4 - r2, 1e-14);
  EXPECT_NEAR(p.values[1], 4, 1e-14);
  EXPECT_NEAR(p.values[2], 4 + r2, 1e-14);
  EXPECT_NEAR(std::abs(p.vectors.col(0).dot(Eigen::Vector3d(1, -r2, 1) / 2)), 1.0, 1e-14);
  EXPECT_NEAR(std::abs(p.vectors.col(1).dot(Eigen::Vector3d(1, 0, -1) / r2)), 1.0, 1e-14);
  EXPECT_NEAR(std::abs(p.vectors.col(2).dot(Eigen::Vector3d(1, r2, 1) / 2)), 1.0, 1e-14);
  // Repeated eigenvalue: [[2,1,1],[1,2,1],[1,1,2]] -> 1, 1, 4; (1,1,1)/sqrt3 for 4.
  s << 2, 2, 2, 1, 1, 1;
  const Principal q = principal_decomposition(s);
  EXPECT_NEAR(q.values[0], 1, 1e-14);
  EXPECT_NEAR(q.values[1], 1, 1e-14);
  EXPECT_NEAR(q.values[2], 4, 1e-14);
  EXPECT_NEAR(std::abs(q.vectors.col(2).dot(Eigen::Vector3d(1, 1, 1) / std::sqrt(3.0))), 1.0, 1e-14);
  const Mat3 A = to_matrix(s);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR((A * q.vectors.col(i) - q.values[i] * q.vectors.col(i)).norm(), 0.0, 1e-14);
  EXPECT_NEAR((q.vectors.transpose() * q.vectors - Mat3::Identity()).norm(), 0.0, 1e-14);
  EXPECT_NEAR((from_principal(q.values, q.vectors) - s).norm(), 0.0, 1e-14);
}

TEST(Principal, RebuildAndPlaneStrainFastPathMatchGeneral) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1, 1), ang(-3.2, 3.2);
  double worst_rebuild = 0, worst_orth = 0, worst_fast = 0, worst_screen = 0;
  for (int n = 0; n < 2000; ++n) {
    // Eigenvalues with clusters (near-equal pairs and triples at several relative gaps).
    const double gap = std::pow(10.0, -(n % 12));
    Eigen::Vector3d v(u(rng), u(rng), u(rng));
    if (n % 3 == 1) v[1] = v[0] + gap * u(rng);
    if (n % 3 == 2) v[1] = v[2] = v[0] + gap * u(rng);
    v *= 1e5;
    const bool plane = n % 2 == 0;
    Mat3 R = plane ? Mat3(Eigen::AngleAxisd(ang(rng), Eigen::Vector3d::UnitZ()))
                   : rotation(ang(rng), ang(rng), ang(rng));
    Sym3 s = from_frame(v, R);
    if (plane) s[4] = s[5] = 0.0;  // exactly plane
    const Principal p = principal_decomposition(s);
    const double sn = s.norm();
    worst_rebuild = std::max(worst_rebuild, (from_principal(p.values, p.vectors) - s).norm() / sn);
    worst_orth = std::max(worst_orth, (p.vectors.transpose() * p.vectors - Mat3::Identity()).norm());
    EXPECT_LE(p.values[0], p.values[1]);
    EXPECT_LE(p.values[1], p.values[2]);
    const Eigen::Vector3d pv = principal_values(s);
    EXPECT_EQ(pv, p.values);
    // The screen's bounds: never inside the extreme values (beyond round-off), and tight where
    // the extreme value is well separated from the middle one (a double root may stay a few
    // per cent outside: the screen then defers to the accurate path).
    const PrincipalBounds b = principal_bounds(s);
    EXPECT_LE(b.lo, p.values[0] + 1e-14 * sn) << n;
    EXPECT_GE(b.hi, p.values[2] - 1e-14 * sn) << n;
    if (p.values[1] - p.values[0] > 0.2 * sn)
      worst_screen = std::max(worst_screen, (p.values[0] - b.lo) / sn);
    if (p.values[2] - p.values[1] > 0.2 * sn)
      worst_screen = std::max(worst_screen, (b.hi - p.values[2]) / sn);
    // Versus Eigen's general solver on the full matrix.
    const Eig ref = reference_eig(s);
    worst_fast = std::max(worst_fast, (p.values - ref.val).norm() / sn);
  }
  std::printf(
      "[principal] worst rebuild %.2e, orthonormality %.2e, values vs Eigen %.2e, screen "
      "bounds of separated extremes %.2e\n",
      worst_rebuild, worst_orth, worst_fast, worst_screen);
  EXPECT_LT(worst_screen, 1e-10);
  EXPECT_LT(worst_rebuild, 1e-14);
  EXPECT_LT(worst_orth, 1e-14);
  EXPECT_LT(worst_fast, 1e-14);
}

// The isolated root of the deviator's cubic: the polynomial start and its Halley step against
// the trigonometric solution cos(acos(c)/3), to round-off over the whole range.
TEST(Principal, LargestCubicRootToRoundOff) {
  double worst = 0;
  for (int i = 0; i <= 100000; ++i) {
    const double c = i / 100000.0;
    worst = std::max(worst, std::abs(detail::largest_cubic_root(c) - std::cos(std::acos(c) / 3.0)));
  }
  EXPECT_LT(worst, 1e-15);
}

// The closed form of the general 3D case on the states where closed forms break: exact double
// and triple roots in rotated frames (cos 3 theta = +-1, where acos loses half the digits), a
// deviator 1e-9 of the mean stress, and off-diagonals at 1e-30 of the diagonal. Each direction
// must satisfy A v = lambda v to round-off of |A|, the frame must stay orthonormal, and a
// well separated value must come with the frame's own direction.
TEST(Principal, ClosedForm3DOnDegenerateStates) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ang(-3.2, 3.2);
  const std::vector<Eigen::Vector3d> spectra = {
      {1, 1, 4}, {-4, 1, 1}, {2, 2, 2}, {-3e5, -3e5, 1e5}, {1e9, 1e9 + 1, 1e9 + 3}, {-7, 0, 7}, {0, 0, 1e-3}};
  double worst_res = 0, worst_orth = 0, worst_dir = 0;
  for (const Eigen::Vector3d& v : spectra)
    for (int n = 0; n < 200; ++n) {
      const Mat3 R = rotation(ang(rng), ang(rng), ang(rng));
      Sym3 s = from_frame(v, R);
      if (n == 0) s << v[0], v[1], v[2], 1e-30 * v.norm(), 0.0, 1e-30 * v.norm();  // nearly diagonal
      const Principal p = principal_decomposition(s);
      const Mat3 A = to_matrix(s);
      for (int i = 0; i < 3; ++i)
        worst_res =
            std::max(worst_res, (A * p.vectors.col(i) - p.values[i] * p.vectors.col(i)).norm() / A.norm());
      worst_orth = std::max(worst_orth, (p.vectors.transpose() * p.vectors - Mat3::Identity()).norm());
      EXPECT_LE(p.values[0], p.values[1]);
      EXPECT_LE(p.values[1], p.values[2]);
      if (n > 0 && v[2] - v[1] > 0.1 * (v[2] - v[0]) && v[1] - v[0] > 0.1 * (v[2] - v[0]))
        for (int i = 0; i < 3; ++i)  // distinct values: each direction is the frame's
          worst_dir = std::max(worst_dir, 1.0 - std::abs(p.vectors.col(i).dot(R.col(i))));
    }
  std::printf("[principal 3D] degenerate states: residual %.2e |A|, orthonormality %.2e, directions %.2e\n",
              worst_res, worst_orth, worst_dir);
  EXPECT_LT(worst_res, 1e-14);
  EXPECT_LT(worst_orth, 1e-14);
  EXPECT_LT(worst_dir,
            1e-12);  // 1 - cos of the angle (2e-13: the 1e9-mean state, built to 2e-7 of its unit gaps)
}

// The eigenvalue-free elastic screen (detail::clearly_elastic) is a sufficient condition: on
// random 3D states it never calls a stress elastic that lies on or outside the Mohr-Coulomb
// surface or beyond the tension cut-off (decided with the accurate principal values), and it
// is tight: on the Lode angle where its bound is attained it accepts stresses up to within
// 1e-9 of the surface.
TEST(MohrCoulomb, EigenvalueFreeScreenIsSufficientAndTight) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  long accepted = 0, by_bounds = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    MohrCoulombParams p;
    p.friction = (trial % 4 == 0 ? 0.0 : 45.0 * (0.5 + 0.5 * u(rng))) * deg;
    p.cohesion = (1.0 + u(rng)) * 20 * kPa;
    if (trial % 3 == 0) p.tension_cutoff = 5 * kPa * (1.0 + u(rng));
    const MohrCoulombConstants k(p);
    Sym3 s;
    for (int i = 0; i < 6; ++i) s[i] = 60 * kPa * u(rng) - (i < 3 ? 40 * kPa : 0.0);
    const Vec3 v = principal_decomposition(s).values;
    // The second screen, on bounds of sigma_1 and sigma_3: also never accepts a state outside.
    // The update stops the bounds' Newton steps at the first iterate that proves the state
    // admissible: it accepts exactly the states that the converged bounds accept.
    const auto admissible = [&k](const PrincipalBounds& b) { return detail::elastic_by_bounds(k, b); };
    ASSERT_EQ(admissible(principal_bounds(s, admissible)), admissible(principal_bounds(s)))
        << "trial " << trial;
    if (detail::elastic_by_bounds(k, principal_bounds(s))) {
      ++by_bounds;
      ASSERT_LT(mohr_coulomb_yield(p, v), 0.0) << "trial " << trial;
      ASSERT_LT(v[2], k.tension_cutoff) << "trial " << trial;
    }
    if (!detail::clearly_elastic(k, s)) continue;
    ++accepted;
    ASSERT_LT(mohr_coulomb_yield(p, v), 0.0) << "trial " << trial;
    ASSERT_LT(v[2], k.tension_cutoff) << "trial " << trial;
  }
  EXPECT_GT(accepted, 100);        // (a screen that accepted nothing would make the loop vacuous)
  EXPECT_GT(by_bounds, accepted);  // the bounds accept more: they see the Lode angle
  // Tightness: a = sqrt(J2) cos t, m = (2/sqrt 3) sqrt(J2) sin t with tan t = -sin(phi)/sqrt 3
  // attains the bound; scaled to f = -1e-9 |p| it must be accepted, to f = +1e-9 |p| refused.
  MohrCoulombParams p;
  p.friction = 30 * deg;
  p.cohesion = 10 * kPa;
  const MohrCoulombConstants k(p);
  const double sp = std::sin(p.friction), t = std::atan(-sp / std::sqrt(3.0)), mean = -100 * kPa;
  const double bound = std::sqrt(1.0 + sp * sp / 3.0);
  for (double rel : {-1e-9, 1e-9}) {
    // f = r bound + mean sin(phi) - c cos(phi) = rel |mean|
    const double r = (rel * std::abs(mean) - mean * sp + k.c_cos_phi) / bound;
    const double a = r * std::cos(t), m = 2.0 / std::sqrt(3.0) * r * std::sin(t);
    Sym3 s;  // principal values p - a - m/2, p + m, p + a - m/2 on the axes
    s << mean - a - 0.5 * m, mean + m, mean + a - 0.5 * m, 0, 0, 0;
    EXPECT_NEAR(mohr_coulomb_yield(p, principal_decomposition(s).values), rel * std::abs(mean),
                1e-2 * std::abs(rel * mean));
    EXPECT_EQ(detail::clearly_elastic(k, s), rel < 0) << rel;
  }
}
