// The hand-unrolled plane-strain stress update update_point_stress<2> (solver/stress_update.hpp:
// scalar push-forward, F and Fe updates and work split, Thesis eq. 4.1-4.4, 4.16, Post eq.
// 72-73; the plane-strain Mohr-Coulomb return of mohr_coulomb_update_plane) equals the general
// 3D update update_point_stress<3> (matrix push-forward, update_stress, 3D Voigt) on the plane
// state embedded in 3D with zero out-of-plane velocity gradient, to round-off (1e-12 relative),
// for every model, on random states: random F and Fe, random stresses within and beyond yield,
// random state variables, random velocity gradient x dt. Compared: stress (and zero
// out-of-plane shear in 3D), every state field, F, Fe (the in-plane block; the 3D Fe also
// tracks 1 - d_eps_p_zz out of plane, which plane strain does not store), strain energy,
// dissipation and volume. And the const law (material/law.hpp) gives what the in-place update
// gives. And the hand-written 3D update equals the matrix form of the same equations on random
// 3D states.
#include <gtest/gtest.h>

#include <cstdio>
#include <numbers>
#include <random>

#include "material/law.hpp"
#include "model_cases.hpp"
#include "solver/stress_update.hpp"

using namespace skred;

namespace {

constexpr double kPa = 1e3;
constexpr double kRel = 1e-12;

using Named = test::NamedModel;
std::vector<Named> models() { return test::model_cases(); }

double rel(double a, double b, double scale) { return std::abs(a - b) / scale; }

}  // namespace

TEST(PlaneStrainPath, HandUnrolledEqualsGeneral3DUpdateOnRandomStates) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Named& n : models()) {
    int plastic = 0;
    double worst_stress = 0, worst_state = 0, worst_F = 0, worst_work = 0;
    const int count = 2000;
    for (int i = 0; i < count; ++i) {
      // Stress: principal values in [-150, 50] kPa in a random in-plane frame (beyond yield for
      // many), sigma_zz in the same range.
      const double th = std::numbers::pi * u(rng);
      const double a = 100 * kPa * u(rng) - 50 * kPa, b = 100 * kPa * u(rng) - 50 * kPa;
      const double c = std::cos(th), s = std::sin(th);
      PointStress<2> s2;
      s2 << a * c * c + b * s * s, a * s * s + b * c * c, 100 * kPa * u(rng) - 50 * kPa, (a - b) * c * s;
      Mat<2> F, Fe, grad_v;
      F << 1 + 0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng), 1 + 0.3 * u(rng);
      Fe << 1 + 0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng), 1 + 0.1 * u(rng);
      // dt grad v up to 1e-3 (elastic-sized) or 2e-2 (large plastic steps).
      const double dt = 1e-3, amp = (i % 3 == 0 ? 20.0 : 1.0);
      grad_v << amp * u(rng), amp * u(rng), amp * u(rng), amp * u(rng);
      PointState st;
      st.plastic_shear_strain = 0.02 * (1 + u(rng));
      st.plastic_volume_strain = 0.01 * u(rng);
      st.volume_strain = 0.0124 + 0.01 * u(rng);
      st.yielding = i % 2;
      const double volume0 = 0.01 * (1.5 + u(rng));

      PointState st2 = st, st3 = st;
      Mat<2> F2 = F, Fe2 = Fe;
      Mat3 F3 = embed3<2>(F, 1.0), Fe3 = embed3<2>(Fe, 1.0);
      PointStress<3> s3 = full_stress<2>(s2);
      const StressUpdateResult r2 = update_point_stress<2>(n.m, grad_v, dt, volume0, s2, st2, F2, Fe2);
      const StressUpdateResult r3 =
          update_point_stress<3>(n.m, embed3<2>(grad_v, 0.0), dt, volume0, s3, st3, F3, Fe3);
      plastic += n.m.plastic() && st2.yielding;

      const double ss = s2.cwiseAbs().maxCoeff() + s3.cwiseAbs().maxCoeff() + kPa;
      double es = 0;
      for (int k = 0; k < 4; ++k) es = std::max(es, rel(s2[k], s3[k], ss));
      es = std::max({es, std::abs(s3[4]) / ss, std::abs(s3[5]) / ss});
      // State: strains relative to their size plus the step's strain increment.
      const double gs = std::abs(dt * grad_v.cwiseAbs().maxCoeff()) + 1e-3;
      const double ek = std::max({rel(st2.plastic_shear_strain, st3.plastic_shear_strain, gs),
                                  rel(st2.plastic_volume_strain, st3.plastic_volume_strain, gs),
                                  rel(st2.volume_strain, st3.volume_strain, gs)});
      EXPECT_EQ(st2.yielding, st3.yielding) << n.name << " sample " << i;
      double ef = 0;
      for (int r = 0; r < 2; ++r)
        for (int c2 = 0; c2 < 2; ++c2)
          ef = std::max({ef, rel(F2(r, c2), F3(r, c2), 1.0), rel(Fe2(r, c2), Fe3(r, c2), 1.0)});
      ef = std::max({ef, rel(F3(2, 2), 1.0, 1.0),
                     std::abs(F3(0, 2)) + std::abs(F3(2, 0)) + std::abs(F3(1, 2)) + std::abs(F3(2, 1)) +
                         std::abs(Fe3(0, 2)) + std::abs(Fe3(2, 0))});
      // Work: relative to V |sigma| |d_eps|.
      const double ws = volume0 * ss * gs;
      const double ew =
          std::max({rel(r2.strain_energy, r3.strain_energy, ws), rel(r2.dissipation, r3.dissipation, ws),
                    rel(r2.volume, r3.volume, volume0)});
      EXPECT_LE(es, kRel) << n.name << " sample " << i << " stress\n" << s2 << "\n\n" << s3;
      EXPECT_LE(ek, kRel) << n.name << " sample " << i << " state";
      EXPECT_LE(ef, kRel) << n.name << " sample " << i << " F, Fe";
      EXPECT_LE(ew, kRel) << n.name << " sample " << i << " work";
      worst_stress = std::max(worst_stress, es);
      worst_state = std::max(worst_state, ek);
      worst_F = std::max(worst_F, ef);
      worst_work = std::max(worst_work, ew);
    }
    std::printf(
        "  %-32s %4d/%d plastic; max rel. diff stress %.1e state %.1e F/Fe %.1e "
        "work %.1e\n",
        n.name, plastic, count, worst_stress, worst_state, worst_F, worst_work);
    if (n.m.plastic()) {
      EXPECT_GE(plastic, count / 5) << n.name << ": too few plastic steps";
    }
  }
}

// The const law (material/law.hpp) runs the in-place update the solver uses on copies: the same
// stress, state and plastic strain, bit for bit, on random 3D and plane states within and
// beyond yield, for every model.
TEST(PlaneStrainPath, ConstLawEqualsTheInPlaceUpdate) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Named& n : models()) {
    for (int i = 0; i < 500; ++i) {
      const bool plane = i % 2 == 0;
      Sym3 s0, deps;
      for (int k = 0; k < 6; ++k) {
        const bool out = plane && k >= 4;
        s0[k] = out ? 0.0 : (k < 3 ? 100 * kPa * u(rng) - 50 * kPa : 30 * kPa * u(rng));
        deps[k] = out ? 0.0 : 5e-3 * u(rng);
      }
      PointState st;
      st.plastic_shear_strain = 0.02 * (1 + u(rng));
      st.volume_strain = 0.0124 + 0.01 * u(rng);
      const LawResult r = evaluate(n.m, s0, deps, st, i % 4 < 2);
      Sym3 s = s0;
      PointState st1 = st;
      const Sym3 dp = update_stress(n.m, s, deps, st1);
      EXPECT_EQ(r.stress, s) << n.name << " sample " << i;
      EXPECT_EQ(r.plastic_strain, dp) << n.name << " sample " << i;
      EXPECT_EQ(r.state.plastic_shear_strain, st1.plastic_shear_strain);
      EXPECT_EQ(r.state.plastic_volume_strain, st1.plastic_volume_strain);
      EXPECT_EQ(r.state.volume_strain, st1.volume_strain);
      EXPECT_EQ(r.state.yielding, st1.yielding);
      EXPECT_EQ(r.has_tangent, i % 4 < 2);
    }
  }
}

namespace {
// Thesis eq. 4.1-4.4 and 4.16, Post eq. 72-73 in matrix form with Eigen's 3 x 3 products: the
// reference the scalar 3D update (solver/kinematics_3d.hpp) must reproduce.
StressUpdateResult matrix_form_update(const Material& mat, const Mat3& grad_v, double dt, double volume0,
                                      Sym3& stress, PointState& state, Mat3& F, Mat3& Fe) {
  const Mat3 G = dt * grad_v, dF = Mat3::Identity() + G;
  const Sym3 deps = sym_voigt<3>(G), old = stress;
  const Sym3 deps_p = update_stress(mat, stress, deps, state);
  stress = to_voigt(dF * to_matrix(stress) * dF.transpose() / dF.determinant());
  F = dF * F;
  const Sym3 deps_e = deps - deps_p;
  Fe = (Mat3::Identity() + to_matrix(deps_e)) * Fe;
  const double volume = volume0 * F.determinant();
  const Sym3 mid = 0.5 * volume * (old + stress);
  return {contract(mid, deps_e), contract(mid, deps_p), volume};
}
}  // namespace

TEST(PlaneStrainPath, Scalar3DUpdateEqualsTheMatrixForm) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Named& n : models()) {
    int plastic = 0;
    double worst = 0;
    const int count = 2000;
    for (int i = 0; i < count; ++i) {
      Sym3 s0;
      for (int k = 0; k < 6; ++k) s0[k] = k < 3 ? 100 * kPa * u(rng) - 50 * kPa : 30 * kPa * u(rng);
      Mat3 F, Fe, grad_v;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          F(r, c) = (r == c) + 0.3 * u(rng);
          Fe(r, c) = (r == c) + 0.1 * u(rng);
          grad_v(r, c) = (i % 3 == 0 ? 20.0 : 1.0) * u(rng);
        }
      PointState st;
      st.plastic_shear_strain = 0.02 * (1 + u(rng));
      st.volume_strain = 0.0124 + 0.01 * u(rng);
      const double dt = 1e-3, volume0 = 0.01 * (1.5 + u(rng));
      Sym3 sa = s0, sb = s0;
      PointState sta = st, stb = st;
      Mat3 Fa = F, Fea = Fe, Fb = F, Feb = Fe;
      const StressUpdateResult ra = update_point_stress<3>(n.m, grad_v, dt, volume0, sa, sta, Fa, Fea);
      const StressUpdateResult rb = matrix_form_update(n.m, grad_v, dt, volume0, sb, stb, Fb, Feb);
      plastic += n.m.plastic() && sta.yielding;
      const double ss = sb.cwiseAbs().maxCoeff() + kPa, ws = volume0 * ss * 0.02;
      const double e = std::max(
          {(sa - sb).cwiseAbs().maxCoeff() / ss, (Fa - Fb).cwiseAbs().maxCoeff(),
           (Fea - Feb).cwiseAbs().maxCoeff(), std::abs(ra.strain_energy - rb.strain_energy) / ws,
           std::abs(ra.dissipation - rb.dissipation) / ws, std::abs(ra.volume - rb.volume) / volume0});
      EXPECT_LE(e, kRel) << n.name << " sample " << i;
      EXPECT_EQ(sta.yielding, stb.yielding);
      EXPECT_EQ(sta.plastic_shear_strain, stb.plastic_shear_strain);
      worst = std::max(worst, e);
    }
    std::printf("  %-32s %4d/%d plastic; max rel. diff %.1e\n", n.name, plastic, count, worst);
    if (n.m.plastic()) {
      EXPECT_GE(plastic, count / 5) << n.name;
    }
  }
}
