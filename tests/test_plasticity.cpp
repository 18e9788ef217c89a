// Mohr-Coulomb / Tresca return mapping (Thesis eq. 5.1-5.4, Paper III §C.3.2 dilation cut-off),
// each check against an outside reference: Hooke's law and the Koiter/KKT conditions of the
// yield and potential functions written out here (plasticity_reference.hpp). The principal
// decomposition and the eigenvalue-free elastic screen are tested in test_principal.cpp, the
// strength paths (R5, von Mises with softening) in test_plasticity_paths.cpp.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "material/mohr_coulomb.hpp"
#include "material/principal.hpp"
#include "plasticity_reference.hpp"

using namespace skred;
using namespace skred::plasticity_test;

namespace {

// Eq. 5.1 with sigma_i as the major and sigma_j as the minor principal stress.
double mc_f(double phi, double c, double si, double sj) {
  return 0.5 * (si - sj) + 0.5 * (si + sj) * std::sin(phi) - c * std::cos(phi);
}
// Gradient of eq. 5.4 in the same form: +(1 + sin psi)/2 on i, -(1 - sin psi)/2 on j.
Eigen::Vector3d mc_b(double psi, int i, int j) {
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  b[i] = 0.5 * (1 + std::sin(psi));
  b[j] = -0.5 * (1 - std::sin(psi));
  return b;
}

// Solves the k x k system (k <= 3) stored in the top-left of A (the rest of A and r is padded
// with the identity and zeros); false if singular. Fixed-size, closed-form 3 x 3 inverse.
bool solve_padded(Mat3 A, Eigen::Vector3d r, int k, Eigen::Vector3d& x) {
  for (int i = k; i < 3; ++i) {
    A.row(i).setZero();
    A.col(i).setZero();
    A(i, i) = 1;
    r[i] = 0;
  }
  const double det = A.determinant();
  if (!(std::abs(det) > 1e-12 * A.row(0).norm() * A.row(1).norm() * A.row(2).norm())) return false;
  x = A.inverse() * r;
  return true;
}

// v in the cone of `gens` (non-negative combination), by least squares over all subsets of at
// most three generators (Caratheodory).
bool in_cone(const Eigen::Vector3d& v, const std::vector<Eigen::Vector3d>& gens, double rel = 1e-9) {
  const double nv = v.norm();
  if (nv == 0.0) return true;
  const int n = static_cast<int>(gens.size());
  for (int mask = 1; mask < (1 << n); ++mask) {
    if (__builtin_popcount(mask) > 3) continue;
    Mat3 Gm = Mat3::Zero();
    int k = 0;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) Gm.col(k++) = gens[i];
    // Least squares by the normal equations of the k chosen generators.
    Eigen::Vector3d x;
    if (!solve_padded(Gm.transpose() * Gm, Gm.transpose() * v, k, x)) continue;
    if ((Gm * x - v).norm() > rel * nv) continue;
    bool ok = true;
    for (int i = 0; i < k; ++i) ok = ok && x[i] * Gm.col(i).norm() >= -rel * nv;
    if (ok) return true;
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
// A Mohr-Coulomb return checked against the Koiter conditions.

struct McCheck {
  MohrCoulombRegion region;
  Eigen::Vector3d sig;     // returned principal stresses (reference eigensolver), ascending
  Eigen::Vector3d ep;      // plastic strain in the trial's principal frame
  double f_rel = 0.0;      // f(sigma) / (c cos phi + |p|)
  double hooke_rel = 0.0;  // |sigma - (trial - C : d_eps_p)| / |trial|
  double coax_rel = 0.0;   // off-diagonal of d_eps_p in the trial frame / |d_eps_p|
  bool kkt = false;        // admissible, on an active surface, d_eps_p in the cone of gradients
  Sym3 stress, deps_p;
};

McCheck check_mc(const McCase& mc, const Elastic& el, const Sym3& s0, const Sym3& deps, double psi_flow,
                 PointState* state_io = nullptr) {
  McCheck r;
  PointState local;
  PointState& st = state_io ? *state_io : local;
  const MohrCoulombConstants k(mc.params());
  const Sym3 trial = s0 + hooke(el, deps);
  r.stress = s0;
  r.deps_p = mohr_coulomb_update(el.constants(), k, r.stress, deps, st, &r.region);
  const Eig et = reference_eig(trial), es = reference_eig(r.stress);
  r.sig = es.val;
  const double scale = mc.c * std::cos(mc.phi) + std::abs(r.stress.head<3>().sum() / 3);
  r.f_rel = mc_f(mc.phi, mc.c, r.sig[2], r.sig[0]) / std::max(scale, 1e-300);
  const double tn = std::max(trial.norm(), 1e-300);
  r.hooke_rel = (r.stress - (trial - hooke(el, r.deps_p))).norm() / tn;
  const Mat3 M = et.vec.transpose() * to_matrix(r.deps_p) * et.vec;
  r.ep = M.diagonal();
  const double en = M.norm();
  r.coax_rel = en > 0 ? (M - Mat3(M.diagonal().asDiagonal())).norm() / en : 0.0;
  // Koiter: active surfaces at the result (all six Mohr-Coulomb planes of the unordered
  // principal space and the three Rankine planes), gradients of the potentials.
  const double tol =
      1e-9 * (scale + std::abs(r.sig[0]) + std::abs(r.sig[2]) + (std::isfinite(mc.t) ? std::abs(mc.t) : 0.0));
  std::vector<Eigen::Vector3d> gens;
  bool admissible = true;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (i == j) continue;
      const double f = mc_f(mc.phi, mc.c, r.sig[i], r.sig[j]);
      admissible = admissible && f <= tol;
      if (std::abs(f) <= tol) gens.push_back(mc_b(psi_flow, i, j));
    }
  if (std::isfinite(mc.t))
    for (int i = 0; i < 3; ++i) {
      admissible = admissible && r.sig[i] - mc.t <= tol;
      if (std::abs(r.sig[i] - mc.t) <= tol) gens.push_back(Eigen::Vector3d::Unit(i));
    }
  const bool plastic = r.region != MohrCoulombRegion::Elastic;
  r.kkt = admissible && (!plastic || (!gens.empty() && in_cone(r.ep, gens)));
  return r;
}

// Brute force over all active sets of at most three of the nine planes of the unordered principal
// space (six Mohr-Coulomb, three Rankine): does any return from the ascending trial principal
// stresses `st` satisfy Koiter's conditions (multipliers >= 0, result admissible)?
bool kkt_return_exists(const McCase& mc, const Elastic& el, const Eigen::Vector3d& st) {
  struct Pl {
    Eigen::Vector3d a, b;
    double k;
  };
  std::vector<Pl> P;
  const double s = std::sin(mc.phi);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j) {
        Eigen::Vector3d a = Eigen::Vector3d::Zero();
        a[i] = 0.5 * (1 + s);
        a[j] = -0.5 * (1 - s);
        P.push_back({a, mc_b(mc.psi, i, j), mc.c * std::cos(mc.phi)});
      }
  if (std::isfinite(mc.t))
    for (int i = 0; i < 3; ++i) P.push_back({Eigen::Vector3d::Unit(i), Eigen::Vector3d::Unit(i), mc.t});
  auto D = [&](const Eigen::Vector3d& v) {
    return Eigen::Vector3d(Eigen::Vector3d::Constant(el.lambda() * v.sum()) + 2 * el.G() * v);
  };
  const double tol = 1e-9 * (mc.c + st.cwiseAbs().maxCoeff() + (std::isfinite(mc.t) ? std::abs(mc.t) : 0));
  const int n = static_cast<int>(P.size());
  for (int mask = 1; mask < (1 << n); ++mask) {
    const int m = __builtin_popcount(mask);
    if (m > 3) continue;
    int id[3], k = 0;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) id[k++] = i;
    Mat3 A = Mat3::Zero();
    Eigen::Vector3d r = Eigen::Vector3d::Zero(), x;
    for (int j = 0; j < m; ++j) {
      r[j] = P[id[j]].a.dot(st) - P[id[j]].k;
      for (int q = 0; q < m; ++q) A(j, q) = P[id[j]].a.dot(D(P[id[q]].b));
    }
    if (!solve_padded(A, r, m, x)) continue;
    Eigen::Vector3d ep = Eigen::Vector3d::Zero();
    bool ok = true;
    for (int q = 0; q < m; ++q) {
      ok = ok && x[q] * D(P[id[q]].b).norm() >= -tol;
      ep += x[q] * P[id[q]].b;
    }
    const Eigen::Vector3d sig = st - D(ep);
    for (const Pl& p : P) ok = ok && p.a.dot(sig) - p.k <= tol;
    if (ok) return true;
  }
  return false;
}

// Does the geometry of the returned stress match the reported region?
bool geometry_matches(MohrCoulombRegion reg, const McCase& mc, const Eigen::Vector3d& s) {
  const double scale = mc.c * std::cos(mc.phi) + s.cwiseAbs().maxCoeff();
  const double tol = 1e-10 * scale, gap = 1e-6 * scale;
  const bool e12 = std::abs(s[0] - s[1]) <= tol, e23 = std::abs(s[1] - s[2]) <= tol;
  const bool f0 = std::abs(mc_f(mc.phi, mc.c, s[2], s[0])) <= tol;
  const bool t3 = std::isfinite(mc.t) && std::abs(s[2] - mc.t) <= tol;
  const bool t2 = std::isfinite(mc.t) && std::abs(s[1] - mc.t) <= tol;
  const bool t1 = std::isfinite(mc.t) && std::abs(s[0] - mc.t) <= tol;
  using R = MohrCoulombRegion;
  switch (reg) {
    case R::Elastic: return true;
    case R::Plane: return f0 && s[1] - s[0] > gap && s[2] - s[1] > gap && !t3;
    case R::CompressionEdge: return f0 && e23 && s[1] - s[0] > gap && !t3;
    case R::ExtensionEdge: return f0 && e12 && s[2] - s[1] > gap && !t3;
    case R::Apex: return e12 && e23 && std::abs(s[0] - mc.c / std::tan(mc.phi)) <= tol;
    case R::Tension: return t3 && !f0 && s[2] - s[1] > gap;
    case R::TensionEdge: return t3 && t2 && !f0 && s[1] - s[0] > gap;
    case R::TensionApex: return t3 && t2 && t1;
    case R::PlaneTension: return f0 && t3 && !e12 && !e23;
    case R::ExtensionCorner: return f0 && t3 && e12;
    case R::CompressionCorner: return f0 && t3 && t2;
  }
  return false;
}

}  // namespace

// =============================================================================================
// Mohr-Coulomb

TEST(MohrCoulomb, YieldFunctionHandComputed) {
  MohrCoulombParams p;
  p.friction = 30 * deg;
  p.cohesion = 10 * kPa;
  // f = 150 + (-150)(1/2) - 10 cos 30 = 75 - 8.6602540378 kPa
  EXPECT_NEAR(mohr_coulomb_yield(p, Eigen::Vector3d(-300, -100, 0) * kPa),
              (75 - 10 * std::sqrt(3.0) / 2) * kPa, 1e-9);
  p.friction = 0;
  EXPECT_NEAR(mohr_coulomb_yield(p, Eigen::Vector3d(-50, 0, 10) * kPa), 20 * kPa, 1e-9);
}

TEST(MohrCoulomb, ElasticPathUnchangedAndCheap) {
  const McCase mc{30 * deg, 10 * kPa, 0};
  PointState st;
  st.plastic_shear_strain = 0.1;
  Sym3 s0;
  s0 << -100, -60, -70, 5, 0, 0;
  s0 *= kPa;
  Sym3 d;
  d << -1e-5, 2e-6, 0, 1e-6, 0, 0;
  Sym3 s = s0;
  const Sym3 ep = mohr_coulomb_update(kSoil.constants(), mc.params(), s, d, st);
  EXPECT_EQ(ep, Sym3::Zero());
  EXPECT_NEAR((s - (s0 + hooke(kSoil, d))).norm(), 0, 1e-9);
  EXPECT_EQ(st.yielding, 0);
  EXPECT_EQ(st.plastic_shear_strain, 0.1);
  EXPECT_DOUBLE_EQ(st.volume_strain, -8e-6);
  // 3D trials just inside / just outside the surface (relative 1e-9), with near-equal principal
  // values where the fast 3D screening is least accurate.
  const double phi = 30 * deg, c = 10 * kPa;
  for (double rel : {-1e-9, 1e-9}) {
    const double s1 = -200 * kPa;
    const double scale = c * std::cos(phi) + std::abs(s1);
    // f = 0.5 (s3 - s1) + 0.5 (s1 + s3) sin(phi) - c cos(phi) = rel * scale, solved for s3.
    const double s3 =
        (rel * scale + c * std::cos(phi) + 0.5 * s1 * (1 - std::sin(phi))) / (0.5 * (1 + std::sin(phi)));
    const Sym3 trial = from_frame(Eigen::Vector3d(s1, s1 * (1 - 1e-9), s3), rotation(0.3, 0.2, 0.1));
    const McCheck r = check_mc(mc, kSoil, trial, Sym3::Zero(), 0);
    if (rel < 0) {
      EXPECT_EQ(r.region, MohrCoulombRegion::Elastic);
      EXPECT_EQ(r.stress, trial);
    } else {
      EXPECT_NE(r.region, MohrCoulombRegion::Elastic);
      EXPECT_LT(std::abs(r.f_rel), 1e-10);
    }
  }
}

// Each region with its flow rule written out.
TEST(MohrCoulomb, PlaneReturnFlowDirection) {
  for (double psi : {0.0, 10 * deg, 30 * deg}) {
    const McCase mc{30 * deg, 10 * kPa, psi};
    const Mat3 R = rotation(0.3, -0.7, 1.1);
    const Sym3 trial = from_frame(Eigen::Vector3d(-300, -150, 0) * kPa, R);
    PointState st;
    const McCheck r = check_mc(mc, kSoil, trial, Sym3::Zero(), psi, &st);
    ASSERT_EQ(r.region, MohrCoulombRegion::Plane) << psi;
    EXPECT_TRUE(geometry_matches(r.region, mc, r.sig));
    EXPECT_TRUE(r.kkt);
    EXPECT_LT(std::abs(r.f_rel), 1e-10);
    EXPECT_LT(r.hooke_rel, 1e-13);
    EXPECT_LT(r.coax_rel, 1e-12);
    // d_eps_p principal ~ (-(1 - sin psi), 0, 1 + sin psi)/2 (eq. 5.3-5.4).
    const double sp = std::sin(psi), en = r.ep.norm();
    EXPECT_GT(r.ep[2], 0);
    EXPECT_LT(std::abs(r.ep[1]) / en, 1e-12);
    EXPECT_LT(std::abs(r.ep[0] * (1 + sp) + r.ep[2] * (1 - sp)) / en, 1e-12);
    // State: gamma_p = 2 sqrt(J2(d_eps_p)), eps_p_v = tr(d_eps_p).
    const Eigen::Vector3d e = r.ep;
    const double j2 =
        ((e[0] - e[1]) * (e[0] - e[1]) + (e[1] - e[2]) * (e[1] - e[2]) + (e[2] - e[0]) * (e[2] - e[0])) / 6;
    EXPECT_NEAR(st.plastic_shear_strain, 2 * std::sqrt(j2), 1e-12 * en);
    EXPECT_NEAR(st.plastic_volume_strain, e.sum(), 1e-12 * en);
    EXPECT_NEAR(e.sum(), en * std::sqrt(2.0) * sp / std::sqrt(1 + sp * sp), 1e-12 * en);
    EXPECT_EQ(st.yielding, 1);
  }
}

TEST(MohrCoulomb, CompressionEdgeReturn) {
  // Triaxial compression trial sigma_1 < sigma_2 = sigma_3.
  for (double psi : {0.0, 10 * deg}) {
    const McCase mc{30 * deg, 10 * kPa, psi};
    const Sym3 trial = from_frame(Eigen::Vector3d(-300, -20, -20) * kPa, rotation(1, 2, 3));
    const McCheck r = check_mc(mc, kSoil, trial, Sym3::Zero(), psi);
    ASSERT_EQ(r.region, MohrCoulombRegion::CompressionEdge);
    EXPECT_TRUE(geometry_matches(r.region, mc, r.sig));
    EXPECT_TRUE(r.kkt);
    EXPECT_LT(std::abs(r.f_rel), 1e-10);
    EXPECT_LT(r.hooke_rel, 1e-13);
    // d_eps_p = m1 b(3,1) + m2 b(2,1), m1, m2 >= 0: e1 = -(e2 + e3)(1 - sin psi)/(1 + sin psi).
    const double sp = std::sin(psi), en = r.ep.norm();
    EXPECT_GT(r.ep[1], 0);
    EXPECT_GT(r.ep[2], 0);
    EXPECT_LT(std::abs(r.ep[0] * (1 + sp) + (r.ep[1] + r.ep[2]) * (1 - sp)) / en, 1e-12);
  }
}

TEST(MohrCoulomb, ExtensionEdgeReturn) {
  for (double psi : {0.0, 10 * deg}) {
    const McCase mc{30 * deg, 10 * kPa, psi};
    const Sym3 trial = from_frame(Eigen::Vector3d(-300, -300, -20) * kPa, rotation(-1, 0.5, 2));
    const McCheck r = check_mc(mc, kSoil, trial, Sym3::Zero(), psi);
    ASSERT_EQ(r.region, MohrCoulombRegion::ExtensionEdge);
    EXPECT_TRUE(geometry_matches(r.region, mc, r.sig));
    EXPECT_TRUE(r.kkt);
    EXPECT_LT(std::abs(r.f_rel), 1e-10);
    EXPECT_LT(r.hooke_rel, 1e-13);
    // d_eps_p = m1 b(3,1) + m2 b(3,2): e3 = -(e1 + e2)(1 + sin psi)/(1 - sin psi), e1, e2 < 0.
    const double sp = std::sin(psi), en = r.ep.norm();
    EXPECT_LT(r.ep[0], 0);
    EXPECT_LT(r.ep[1], 0);
    EXPECT_LT(std::abs(r.ep[2] * (1 - sp) + (r.ep[0] + r.ep[1]) * (1 + sp)) / en, 1e-12);
  }
}

TEST(MohrCoulomb, ApexReturn) {
  const double apex = 10 * kPa / std::tan(30 * deg);
  for (double psi : {0.0, 10 * deg, 30 * deg}) {
    const McCase mc{30 * deg, 10 * kPa, psi};
    const Sym3 trial = from_frame(Eigen::Vector3d(50, 60, 70) * kPa, rotation(0.2, 0.4, 0.6));
    const McCheck r = check_mc(mc, kSoil, trial, Sym3::Zero(), psi);
    ASSERT_EQ(r.region, MohrCoulombRegion::Apex);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.sig[i], apex, 1e-10 * apex);
    EXPECT_LT(r.hooke_rel, 1e-13);  // d_eps_p = C^-1 : (trial - apex)
    // psi > 0: the trial lies in the cone of the D b_i, so d_eps_p is a non-negative combination
    // of the potential gradients. psi = 0: the flow rule is isochoric and no return can lower the
    // mean stress to the apex; the apex is still the only admissible point reached (Clausen).
    if (psi > 0) {
      EXPECT_TRUE(r.kkt) << psi;
    }
  }
  // Cohesionless: a tensile trial returns to zero stress.
  const McCase sand{35 * deg, 0, 5 * deg};
  const Sym3 trial = from_frame(Eigen::Vector3d(-1, 10, 30) * kPa, rotation(0.1, 0.2, 0.3));
  const McCheck r = check_mc(sand, kSoil, trial, Sym3::Zero(), 5 * deg);
  ASSERT_EQ(r.region, MohrCoulombRegion::Apex);
  EXPECT_LT(r.stress.norm(), 1e-12 * trial.norm());
  EXPECT_TRUE(r.kkt);
}

TEST(MohrCoulomb, TrescaHasEdgesButNoApex) {
  const McCase tr{0, 20 * kPa, 0};
  const Mat3 R = rotation(0.5, 0.1, -0.4);
  struct {
    Eigen::Vector3d v;
    MohrCoulombRegion reg;
  } cases[] = {{Eigen::Vector3d(-100, -50, 0), MohrCoulombRegion::Plane},
               {Eigen::Vector3d(-100, 0, 0), MohrCoulombRegion::CompressionEdge},
               {Eigen::Vector3d(-100, -100, 0), MohrCoulombRegion::ExtensionEdge},
               // Tension: the hydrostatic part is unlimited.
               {Eigen::Vector3d(1000, 1050, 1100), MohrCoulombRegion::Plane}};
  for (const auto& c : cases) {
    const McCheck r = check_mc(tr, kSoil, from_frame(c.v * kPa, R), Sym3::Zero(), 0);
    EXPECT_EQ(r.region, c.reg) << c.v.transpose();
    EXPECT_TRUE(geometry_matches(r.region, tr, r.sig));
    EXPECT_TRUE(r.kkt);
    EXPECT_NEAR(r.sig[2] - r.sig[0], 2 * tr.c, 1e-10 * tr.c);
    EXPECT_NEAR(r.ep.sum(), 0.0, 1e-12 * r.ep.norm());  // psi = 0: isochoric
    // Pressure is kept by Tresca with psi = 0.
    EXPECT_NEAR(r.sig.sum(), c.v.sum() * kPa, 1e-9 * c.v.norm() * kPa);
  }
  const McCheck hyd =
      check_mc(tr, kSoil, from_frame(Eigen::Vector3d(1, 1, 1) * 1e4 * kPa, R), Sym3::Zero(), 0);
  EXPECT_EQ(hyd.region, MohrCoulombRegion::Elastic);
}

TEST(MohrCoulomb, TensionCutOff) {
  using R = MohrCoulombRegion;
  // phi = 30, c = 10 kPa: apex c cot(phi) = 17.3 kPa; cut-off t = 2 kPa.
  const McCase mc{30 * deg, 10 * kPa, 10 * deg, 2 * kPa};
  const Mat3 Q = rotation(0.7, -0.2, 0.9);
  struct {
    Eigen::Vector3d v;
    R reg;
  } cases[] = {{Eigen::Vector3d(-10, -5, 6), R::Tension},
               {Eigen::Vector3d(-10, 6, 6), R::TensionEdge},
               {Eigen::Vector3d(10, 10, 10), R::TensionApex},
               {Eigen::Vector3d(-40, -10, 40), R::PlaneTension},
               {Eigen::Vector3d(-20, -20, 80), R::ExtensionCorner},
               {Eigen::Vector3d(-40, 40, 40), R::CompressionCorner},
               {Eigen::Vector3d(-60, -20, -5), R::Plane}};
  for (const auto& c : cases) {
    const McCheck r = check_mc(mc, kSoil, from_frame(c.v * kPa, Q), Sym3::Zero(), mc.psi);
    EXPECT_EQ(r.region, c.reg) << c.v.transpose() << " -> " << r.sig.transpose() / kPa;
    EXPECT_TRUE(geometry_matches(r.region, mc, r.sig)) << c.v.transpose();
    EXPECT_TRUE(r.kkt) << c.v.transpose();
    EXPECT_LE(r.sig[2], mc.t * (1 + 1e-12));
    EXPECT_LT(r.hooke_rel, 1e-13);
  }
  // A cut-off at or above the apex has no effect.
  McCase high = mc;
  high.t = 10 * kPa / std::tan(30 * deg);
  const Sym3 trial = from_frame(Eigen::Vector3d(50, 60, 70) * kPa, Q);
  EXPECT_EQ(check_mc(high, kSoil, trial, Sym3::Zero(), mc.psi).region, R::Apex);
  // Tresca with a cut-off: plane return limited by sigma_3 <= t.
  const McCase tc{0, 20 * kPa, 0, 5 * kPa};
  const McCheck r = check_mc(tc, kSoil, from_frame(Eigen::Vector3d(0, 10, 30) * kPa, Q), Sym3::Zero(), 0);
  EXPECT_TRUE(r.kkt);
  EXPECT_NEAR(r.sig[2], 5 * kPa, 1e-9);
}

// Random trials (3D and plane strain), many parameter sets: every return satisfies the Koiter
// conditions and the region it reports.
TEST(MohrCoulomb, RandomTrialsSatisfyKoiterConditions) {
  const double inf = std::numeric_limits<double>::infinity();
  const McCase cases[] = {{30 * deg, 10 * kPa, 0, inf},
                          {30 * deg, 10 * kPa, 10 * deg, inf},
                          {30 * deg, 10 * kPa, 30 * deg, inf},
                          {42 * deg, 1 * kPa, 0, inf},
                          {35 * deg, 0, 5 * deg, inf},
                          {0, 20 * kPa, 0, inf},
                          {30 * deg, 10 * kPa, 10 * deg, 2 * kPa},
                          {30 * deg, 10 * kPa, 0, -3 * kPa},
                          {0, 20 * kPa, 0, 5 * kPa},
                          {35 * deg, 0, 5 * deg, 0.0}};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1), ang(-3.2, 3.2);
  int counts[11] = {};
  int fails = 0;
  double worst_f = 0, worst_hooke = 0;
  int gaps = 0;
  for (const McCase& mc : cases)
    for (int n = 0; n < 4000; ++n) {
      Eigen::Vector3d v(u(rng), u(rng), u(rng));
      v = v * 200 * kPa + Eigen::Vector3d::Constant(-50 * kPa * (1 + u(rng)));
      if (n % 7 == 0) v[1] = v[2];  // exact ties in the trial
      if (n % 7 == 1) v[0] = v[1];
      const bool plane = n % 2 == 0;
      const Mat3 R = plane ? Mat3(Eigen::AngleAxisd(ang(rng), Eigen::Vector3d::UnitZ()))
                           : rotation(ang(rng), ang(rng), ang(rng));
      Sym3 trial = from_frame(v, R);
      if (plane) trial[4] = trial[5] = 0;
      const McCheck r = check_mc(mc, kSoil, trial, Sym3::Zero(), mc.psi);
      ++counts[int(r.region)];
      using MR = MohrCoulombRegion;
      const bool on_mc = r.region != MR::Elastic && r.region != MR::Tension && r.region != MR::TensionEdge &&
                         r.region != MR::TensionApex;
      if (on_mc) worst_f = std::max(worst_f, std::abs(r.f_rel));
      worst_hooke = std::max(worst_hooke, r.hooke_rel);
      // Where Koiter's conditions have no solution at all (non-associated flow, e.g. psi = 0 and a
      // mean trial stress above the apex) the apex return is accepted.
      bool gap = false;
      if (!r.kkt && r.region == MR::Apex && !kkt_return_exists(mc, kSoil, reference_eig(trial).val)) {
        gap = true;
        ++gaps;
      }
      const bool ok = (r.kkt || gap) && (!on_mc || std::abs(r.f_rel) < 1e-10) &&
                      geometry_matches(r.region, mc, r.sig) && r.hooke_rel < 1e-12 && r.coax_rel < 1e-10 &&
                      (!plane || (r.stress[4] == 0 && r.stress[5] == 0));
      if (!ok && ++fails < 10)
        ADD_FAILURE() << "kkt exists " << kkt_return_exists(mc, kSoil, reference_eig(trial).val) << " "
                      << "phi " << mc.phi / deg << " c " << mc.c << " psi " << mc.psi / deg << " t " << mc.t
                      << " trial " << v.transpose() << " region " << int(r.region) << " -> "
                      << r.sig.transpose() << " kkt " << r.kkt;
    }
  std::printf(
      "[MC random] regions: elastic %d plane %d c-edge %d e-edge %d apex %d tension %d "
      "t-edge %d t-apex %d plane-t %d e-corner %d c-corner %d\n",
      counts[0], counts[1], counts[2], counts[3], counts[4], counts[5], counts[6], counts[7], counts[8],
      counts[9], counts[10]);
  std::printf("[MC random] apex returns where no Koiter solution exists: %d\n", gaps);
  std::printf(
      "[MC random] worst |f|/(c cos phi + |p|) %.2e, worst |sigma - (trial - C:deps_p)|/|trial| "
      "%.2e\n",
      worst_f, worst_hooke);
  for (int i = 0; i < 11; ++i) EXPECT_GT(counts[i], 0) << "region " << i << " never hit";
  EXPECT_EQ(fails, 0);
}

TEST(MohrCoulomb, DilationCutOffAtMaxVoidRatio) {
  McCase mc{35 * deg, 0, 10 * deg};
  MohrCoulombParams p = mc.params();
  p.initial_void_ratio = 0.5;
  p.max_void_ratio = 0.8;
  const MohrCoulombConstants k(p);
  const Sym3 s0 = from_frame(Eigen::Vector3d(-300, -150, -60) * kPa, rotation(0.1, 0.2, 0.3));
  Sym3 d = Sym3::Zero();
  d[0] = 1e-4;  // tr(d) = 1e-4
  const double ev_max = std::log(1.8 / 1.5);
  auto void_ratio = [&](double ev) { return (1 + 0.5) * std::exp(ev) - 1; };
  for (double margin : {-1e-9, 1e-9, -1e-3, 1e-3}) {
    PointState st;
    st.volume_strain = ev_max + margin - 1e-4;  // after the update: ev_max + margin
    Sym3 s = s0;
    MohrCoulombRegion reg;
    const Sym3 ep = mohr_coulomb_update(kSoil.constants(), k, s, d, st, &reg);
    ASSERT_EQ(reg, MohrCoulombRegion::Plane);
    const double e = void_ratio(st.volume_strain);
    const double tr = ep[0] + ep[1] + ep[2], en = to_matrix(ep).norm();
    if (e >= 0.8) {
      EXPECT_LT(std::abs(tr), 1e-13 * en) << margin;  // psi = 0
      EXPECT_NEAR(st.plastic_volume_strain, tr, 1e-13 * en);
    } else {
      // psi = 10 deg: tr = sqrt2 sin psi / sqrt(1 + sin^2 psi) |d_eps_p| on the plane.
      const double sp = std::sin(10 * deg);
      EXPECT_NEAR(tr, en * std::sqrt(2.0) * sp / std::sqrt(1 + sp * sp), 1e-12 * en) << margin;
    }
    EXPECT_EQ(margin > 0, e >= 0.8);
  }
}

// A step from inside the surface to beyond it ends on the surface; a proportional plastic path
// cut into many small steps gives the same stress as one big step while it stays in one region
// (the return onto a plane or a line is an affine projection along a fixed direction).
TEST(MohrCoulomb, ConsistencyAcrossIncrements) {
  const McCase mc{30 * deg, 10 * kPa, 10 * deg};
  const Mat3 R = rotation(0.4, 0.8, -0.3);
  // Elastic starts coaxial with the path (ties kept for the edge paths).
  struct {
    Eigen::Vector3d start, dir;
    MohrCoulombRegion reg;
  } paths[] = {
      {Eigen::Vector3d(-100, -70, -50), Eigen::Vector3d(-1, -0.3, 0.5), MohrCoulombRegion::Plane},
      {Eigen::Vector3d(-100, -50, -50), Eigen::Vector3d(-1, 0.5, 0.5), MohrCoulombRegion::CompressionEdge},
      {Eigen::Vector3d(-100, -100, -50), Eigen::Vector3d(-0.5, -0.5, 1), MohrCoulombRegion::ExtensionEdge}};
  for (const auto& pth : paths) {
    const Sym3 s0 = from_frame(pth.start * kPa, R);
    const Sym3 dtot = from_frame(pth.dir * 2e-2, R);
    // One big step from the elastic start crosses the surface.
    PointState big_state;
    const McCheck big = check_mc(mc, kSoil, s0, dtot, mc.psi, &big_state);
    ASSERT_EQ(big.region, pth.reg);
    EXPECT_LT(std::abs(big.f_rel), 1e-10);
    EXPECT_TRUE(big.kkt);
    // The same path in N small steps: elastic ones, the one that crosses the surface, plastic ones.
    PointState st;
    Sym3 s = s0;
    const int N = 400;
    Sym3 sum_ep = Sym3::Zero();
    for (int i = 0; i < N; ++i) {
      const McCheck r = check_mc(mc, kSoil, s, dtot / N, mc.psi, &st);
      s = r.stress;
      sum_ep += r.deps_p;
      if (r.region != MohrCoulombRegion::Elastic) {
        EXPECT_EQ(r.region, pth.reg) << i;
        EXPECT_LT(std::abs(r.f_rel), 1e-10) << i;
      }
    }
    // Every plastic step returned to the same plane/line along the same direction, and composing
    // such affine projections gives the single projection: the end states agree to round-off.
    EXPECT_LT((s - big.stress).norm() / big.stress.norm(), 1e-10);
    EXPECT_LT((sum_ep - big.deps_p).norm() / big.deps_p.norm(), 1e-9);
    EXPECT_NEAR(st.plastic_volume_strain, big_state.plastic_volume_strain,
                1e-9 * std::abs(big_state.plastic_volume_strain));
    EXPECT_NEAR(st.volume_strain, big_state.volume_strain, 1e-15);
  }
}
