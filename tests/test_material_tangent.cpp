// The consistent tangents of the const laws (material/law.hpp) against central finite
// differences of the same law's own update (Acosta eq. 5 and 10 need the exact derivative of
// the discrete update): elastic, Mohr-Coulomb in every return region of the principal-stress
// return (Thesis eq. 5.1-5.4 after Clausen et al.), with the tension and the dilation cut-off,
// Tresca, and von Mises with linear softening on both sides of the kink (Acosta §3.2).
//
// Convention (material/law_result.hpp): tangent(i, j) = d sigma[i] / d deps[j] with tensor shear
// strains in deps; the finite differences perturb deps[j] by +-h in exactly that convention.
// Step h = 1e-7 for strain increments and stress/E of order 1e-3 to 1e-2, central differences
// with h and h/2 combined by Richardson extrapolation: the truncation error (the spin of the
// principal directions varies on the scale (lambda_i - lambda_j)/E, down to ~1e-5 for nearly
// equal trial principal stresses among the random states) is O((h/1e-5)^4) = 1e-8 relative,
// the round-off ~ 1e-16 |sigma| / (h E) ~ 1e-11 relative. (Plain central differences with h
// reach 6e-7 there.) Tolerance: max_ij |tangent - FD| <= 1e-6 max_ij |C| for every state.
// A finite difference is only taken when both perturbed updates stay in the base point's
// return region (asserted for the hand-picked states; random states straddling a region
// boundary are skipped and counted).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <numbers>
#include <random>

#include "material/law.hpp"

using namespace skred;

namespace {

constexpr double kPa = 1e3;
constexpr double deg = std::numbers::pi / 180.0;
constexpr double kStep = 1e-7;
constexpr double kTol = 1e-6;

Material make(Model model, double E = 1e7, double nu = 0.3) {
  Material m;
  m.model = model;
  m.density = 2000.0;
  m.elastic = {E, nu};
  m.prepare();
  return m;
}

Material mohr_coulomb(double phi, double c, double psi, double t = INFINITY) {
  Material m = make(Model::MohrCoulomb);
  m.mohr_coulomb.friction = phi;
  m.mohr_coulomb.cohesion = c;
  m.mohr_coulomb.dilation = psi;
  m.mohr_coulomb.tension_cutoff = t;
  m.prepare();
  return m;
}

Material von_mises(double cp, double cr, double H) {
  Material m = make(Model::VonMises);
  m.von_mises = {cp, cr, H};
  m.prepare();
  return m;
}

// A region label of a law evaluation (the MC region, the von Mises branch, or 0).
using Law = std::function<LawResult(const Sym3& deps, int* region)>;

Law law_of(const Material& m, const Sym3& s0, const PointState& st) {
  return [m, s0, st](const Sym3& deps, int* region) {
    if (m.model == Model::MohrCoulomb || m.model == Model::Tresca) {
      MohrCoulombRegion r;
      LawResult out =
          mohr_coulomb_evaluate(m.elastic_constants, m.mohr_coulomb_constants, s0, deps, st, true, &r);
      *region = int(r);
      return out;
    }
    if (m.model == Model::VonMises) {
      VonMisesBranch b;
      LawResult out = von_mises_evaluate(m.elastic_constants, m.von_mises, s0, deps, st, true, &b);
      *region = int(b);
      return out;
    }
    *region = 0;
    return evaluate(m, s0, deps, st, true);
  };
}

struct FdCheck {
  bool same_region = true;  // both perturbed updates in the base region
  int region = 0;
  double error = 0.0;    // max |tangent - FD| / max |C|
  double plastic = 0.0;  // max |tangent - C| / max |C| (how far from elastic)
  Mat6 tangent, fd;
};

FdCheck fd_check(const Material& m, const Law& law, const Sym3& deps) {
  FdCheck c;
  const LawResult base = law(deps, &c.region);
  EXPECT_TRUE(base.has_tangent);
  c.tangent = base.tangent;
  // Central differences with steps h and h/2, Richardson-extrapolated (4 D_{h/2} - D_h)/3.
  for (int j = 0; j < 6; ++j) {
    Sym3 d[2];
    for (int k = 0; k < 2; ++k) {
      const double h = kStep / (1 << k);
      int rp, rm;
      const Sym3 e = h * Sym3::Unit(j);
      const Sym3 sp = law(deps + e, &rp).stress, sm = law(deps - e, &rm).stress;
      c.same_region = c.same_region && rp == c.region && rm == c.region;
      d[k] = (sp - sm) / (2.0 * h);
    }
    c.fd.col(j) = (4.0 * d[1] - d[0]) / 3.0;
  }
  const Mat6 C = elastic_stiffness(m.elastic_constants);
  const double scale = C.cwiseAbs().maxCoeff();
  c.error = (c.tangent - c.fd).cwiseAbs().maxCoeff() / scale;
  c.plastic = (c.tangent - C).cwiseAbs().maxCoeff() / scale;
  return c;
}

Mat3 random_rotation(std::mt19937& rng, bool plane) {
  std::uniform_real_distribution<double> a(-std::numbers::pi, std::numbers::pi);
  const Mat3 z = Eigen::AngleAxisd(a(rng), Vec3::UnitZ()).toRotationMatrix();
  if (plane) return z;
  return z * Eigen::AngleAxisd(a(rng), Vec3::UnitY()) * Eigen::AngleAxisd(a(rng), Vec3::UnitX());
}

// A step whose trial stress has the principal values `trial` (any order) in the frame R: a
// random strain increment (out-of-plane shear zero when `plane`), sigma^k = trial - C d_eps.
struct Step {
  Sym3 s0, deps;
};
Step step_to(const Material& m, const Vec3& trial, const Mat3& R, std::mt19937& rng, bool plane) {
  std::uniform_real_distribution<double> u(-2e-3, 2e-3);
  Step s;
  for (int i = 0; i < 6; ++i) s.deps[i] = (plane && i >= 4) ? 0.0 : u(rng);
  s.s0 = to_voigt(R * trial.asDiagonal() * R.transpose()) - elastic_stiffness(m.elastic_constants) * s.deps;
  return s;
}

const char* region_name(MohrCoulombRegion r) {
  static const char* names[] = {"Elastic",      "Plane",           "CompressionEdge",  "ExtensionEdge",
                                "Apex",         "Tension",         "TensionEdge",      "TensionApex",
                                "PlaneTension", "ExtensionCorner", "CompressionCorner"};
  return names[int(r)];
}

// Random trial stresses (principal values uniform in [lo, hi] kPa, general and plane-strain
// orientations); every sample whose FD stays in one region is checked. Returns the number of
// checked samples and the largest error per region.
std::map<MohrCoulombRegion, std::pair<int, double>> sweep_mc(const Material& m, double lo, double hi, int n,
                                                             unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo * kPa, hi * kPa);
  std::map<MohrCoulombRegion, std::pair<int, double>> out;
  int skipped = 0;
  for (int i = 0; i < n; ++i) {
    const bool plane = i % 2 == 0;
    const Vec3 trial(u(rng), u(rng), u(rng));
    const Step s = step_to(m, trial, random_rotation(rng, plane), rng, plane);
    const FdCheck c = fd_check(m, law_of(m, s.s0, PointState{}), s.deps);
    if (!c.same_region) {
      ++skipped;
      continue;
    }
    auto& [count, worst] = out[MohrCoulombRegion(c.region)];
    ++count;
    worst = std::max(worst, c.error);
    EXPECT_LE(c.error, kTol) << region_name(MohrCoulombRegion(c.region)) << " sample " << i << "\nanalytic\n"
                             << c.tangent << "\nFD\n"
                             << c.fd;
  }
  for (const auto& [r, cw] : out)
    std::printf("  %-17s %5d states, max FD error %.2e\n", region_name(r), cw.first, cw.second);
  std::printf("  (%d states straddling a region boundary skipped)\n", skipped);
  return out;
}

}  // namespace

TEST(MaterialTangent, ElasticIsHookeAndMatchesFiniteDifferences) {
  const Material m = make(Model::LinearElastic);
  const Sym3 s0 = (Sym3() << -50, -80, -60, 10, -5, 3).finished() * kPa;
  const Sym3 deps = (Sym3() << 1e-3, -2e-3, 5e-4, 3e-4, -1e-3, 2e-4).finished();
  const FdCheck c = fd_check(m, law_of(m, s0, PointState{}), deps);
  const Mat6 C = elastic_stiffness(m.elastic_constants);
  EXPECT_EQ(c.tangent, C);
  // Hooke written out: d sigma_xy = 2 G d eps_xy (tensor shear), d sigma_xx/d eps_yy = lambda.
  const double G = 1e7 / 2.6, lambda = 1e7 * 0.3 / (1.3 * 0.4);
  EXPECT_NEAR(C(3, 3), 2 * G, 1e-9 * G);
  EXPECT_NEAR(C(0, 1), lambda, 1e-9 * G);
  EXPECT_NEAR(C(0, 0), lambda + 2 * G, 1e-9 * G);
  EXPECT_LE(c.error, kTol);
  std::printf("  elastic: max FD error %.2e\n", c.error);
}

TEST(MaterialTangent, ElasticInsideTheYieldSurfaceGivesC) {
  // Trials well inside the surface: the plastic laws are elastic and return exactly C.
  const Sym3 s0 = (Sym3() << -60, -80, -70, 5, 2, -3).finished() * kPa;
  const Sym3 deps = (Sym3() << 1e-4, -1e-4, 0, 5e-5, 0, 0).finished();
  for (const Material& m : {mohr_coulomb(30 * deg, 10 * kPa, 10 * deg), mohr_coulomb(0.0, 50 * kPa, 0.0),
                            von_mises(50 * kPa, 10 * kPa, -1e5)}) {
    const FdCheck c = fd_check(m, law_of(m, s0, PointState{}), deps);
    EXPECT_EQ(c.region, 0);  // MohrCoulombRegion::Elastic, VonMisesBranch::Elastic
    EXPECT_TRUE(c.same_region);
    EXPECT_EQ(c.tangent, elastic_stiffness(m.elastic_constants));
    EXPECT_LE(c.error, kTol);
  }
}

TEST(MaterialTangent, MohrCoulombEveryRegionMatchesFiniteDifferences) {
  using R = MohrCoulombRegion;
  // Without the cut-off: plane, both edges and the apex (c cot phi = 17.3 kPa).
  std::printf("Mohr-Coulomb phi 30, psi 10, c 10 kPa:\n");
  const Material m = mohr_coulomb(30 * deg, 10 * kPa, 10 * deg);
  const auto a = sweep_mc(m, -200, 60, 2000, 1);
  for (R r : {R::Elastic, R::Plane, R::CompressionEdge, R::ExtensionEdge, R::Apex})
    EXPECT_GE(a.count(r) ? a.at(r).first : 0, 5) << region_name(r);
  // With a tension cut-off t = 5 kPa below the apex: the Rankine plane, edge and apex, the
  // plane/Rankine intersection and both corners.
  std::printf("Mohr-Coulomb phi 30, psi 10, c 10 kPa, tension cut-off 5 kPa:\n");
  const Material mt = mohr_coulomb(30 * deg, 10 * kPa, 10 * deg, 5 * kPa);
  const auto b = sweep_mc(mt, -120, 40, 4000, 2);
  for (R r : {R::Plane, R::CompressionEdge, R::ExtensionEdge, R::Tension, R::TensionEdge, R::TensionApex,
              R::PlaneTension, R::ExtensionCorner, R::CompressionCorner})
    EXPECT_GE(b.count(r) ? b.at(r).first : 0, 3) << region_name(r);
  // Associated flow (psi = phi) too.
  std::printf("Mohr-Coulomb phi 35, psi 35, c 5 kPa:\n");
  const auto c = sweep_mc(mohr_coulomb(35 * deg, 5 * kPa, 35 * deg), -200, 20, 1000, 3);
  EXPECT_GE(c.count(R::Plane) ? c.at(R::Plane).first : 0, 5);
}

TEST(MaterialTangent, MohrCoulombHandPickedRegionsAreAssertedAndPlastic) {
  using R = MohrCoulombRegion;
  const Material m = mohr_coulomb(30 * deg, 10 * kPa, 10 * deg);
  const Material mt = mohr_coulomb(30 * deg, 10 * kPa, 10 * deg, 5 * kPa);
  struct Case {
    const Material* m;
    Vec3 trial;  // kPa
    R region;
  };
  const Case cases[] = {
      {&m, {-150, -70, 0}, R::Plane},
      {&m, {-150, -3, 0}, R::CompressionEdge},
      {&m, {-150, -147, 0}, R::ExtensionEdge},
      {&m, {30, 35, 40}, R::Apex},
      {&mt, {-10, -5, 8}, R::Tension},
      {&mt, {-10, 7, 8}, R::TensionEdge},
      {&mt, {10, 12, 14}, R::TensionApex},
      // Equal trial principal stresses (the spin factors' limit): on the edge and apex lines.
      {&m, {-150, -150, 0}, R::ExtensionEdge},
      {&m, {-150, 0, 0}, R::CompressionEdge},
      {&m, {30, 30, 30}, R::Apex},
  };
  std::mt19937 rng(7);
  for (const Case& k : cases)
    for (bool plane : {true, false}) {
      const Step s = step_to(*k.m, k.trial * kPa, random_rotation(rng, plane), rng, plane);
      const FdCheck c = fd_check(*k.m, law_of(*k.m, s.s0, PointState{}), s.deps);
      EXPECT_EQ(R(c.region), k.region) << region_name(R(c.region));
      EXPECT_TRUE(c.same_region);
      EXPECT_LE(c.error, kTol) << region_name(k.region) << "\n" << c.tangent << "\n\n" << c.fd;
      EXPECT_GE(c.plastic, 1e-2) << "the tangent should differ from C in a plastic region";
    }
}

TEST(MaterialTangent, TrescaPlaneAndEdgesMatchFiniteDifferences) {
  using R = MohrCoulombRegion;
  std::printf("Tresca s_u 30 kPa:\n");
  Material m = make(Model::Tresca);
  m.mohr_coulomb.cohesion = 30 * kPa;
  m.prepare();
  const auto a = sweep_mc(m, -150, 50, 1500, 4);
  for (R r : {R::Elastic, R::Plane, R::CompressionEdge, R::ExtensionEdge})
    EXPECT_GE(a.count(r) ? a.at(r).first : 0, 5) << region_name(r);
  EXPECT_EQ(a.count(R::Apex), 0u);  // Tresca has no apex
}

TEST(MaterialTangent, MohrCoulombDilationCutOffUsesTheDilationInUse) {
  // e0 = 0.6, e_max = 0.7: psi = 0 once the volume strain reaches ln(1.7/1.6) = 0.0606. The
  // update jumps at the switch; on each side the tangent is that of the dilation in use.
  Material m = mohr_coulomb(30 * deg, 10 * kPa, 15 * deg);
  m.mohr_coulomb.initial_void_ratio = 0.6;
  m.mohr_coulomb.max_void_ratio = 0.7;
  m.prepare();
  std::mt19937 rng(11);
  Mat6 tangent[2];
  for (int past = 0; past < 2; ++past) {
    PointState st;
    st.volume_strain = past ? 0.1 : 0.0;
    const Step s = step_to(m, Vec3(-150, -70, 0) * kPa, random_rotation(rng, false), rng, false);
    const FdCheck c = fd_check(m, law_of(m, s.s0, st), s.deps);
    EXPECT_EQ(MohrCoulombRegion(c.region), MohrCoulombRegion::Plane);
    EXPECT_TRUE(c.same_region);
    EXPECT_LE(c.error, kTol);
    tangent[past] = c.tangent;
    // The plastic volume strain is zero after the cut-off (psi = 0), positive before.
    const LawResult r = evaluate(m, s.s0, s.deps, st, false);
    if (past) {
      EXPECT_NEAR(r.state.plastic_volume_strain, 0.0, 1e-15);
    } else {
      EXPECT_GT(r.state.plastic_volume_strain, 0.0);
    }
  }
  EXPECT_GT((tangent[0] - tangent[1]).cwiseAbs().maxCoeff(),
            1e-3 * elastic_stiffness(m.elastic_constants).maxCoeff());
}

TEST(MaterialTangent, VonMisesSofteningBothSidesOfTheKink) {
  // c_p = 12 kPa, c_r = 3 kPa; H_s = -1 MPa (G = 3.85 MPa, G + H_s > 0): kink at kappa = 9e-3.
  const Material m = von_mises(12 * kPa, 3 * kPa, -1e6);
  const Material perfect = von_mises(12 * kPa, 12 * kPa, 0.0);
  struct Case {
    double kappa, q;  // state and trial sqrt(J2) [kPa]
    VonMisesBranch branch;
  };
  const Case cases[] = {
      {0.0, 14, VonMisesBranch::Softening},    // from the peak, on the softening line
      {5e-3, 9, VonMisesBranch::Softening},    // before the kink (c = 7 kPa)
      {8.9e-3, 30, VonMisesBranch::Residual},  // a step across the kink lands on c_r
      {2e-2, 6, VonMisesBranch::Residual},     // at residual
  };
  std::mt19937 rng(5);
  for (const Case& k : cases)
    for (bool plane : {true, false}) {
      // Trial deviator of the given sqrt(J2) and a random Lode angle and orientation.
      std::uniform_real_distribution<double> u(-1, 1);
      Vec3 d(u(rng), u(rng), u(rng));
      d.array() -= d.mean();
      d *= k.q * kPa / std::sqrt(0.5 * d.squaredNorm());
      const Step s = step_to(m, d + Vec3::Constant(-50 * kPa), random_rotation(rng, plane), rng, plane);
      PointState st;
      st.plastic_shear_strain = k.kappa;
      const FdCheck c = fd_check(m, law_of(m, s.s0, st), s.deps);
      EXPECT_EQ(VonMisesBranch(c.region), k.branch) << k.kappa;
      EXPECT_TRUE(c.same_region);
      EXPECT_LE(c.error, kTol) << k.kappa << "\n" << c.tangent << "\n\n" << c.fd;
      std::printf("  von Mises kappa %.1e q %2.0f kPa: branch %d, max FD error %.2e\n", k.kappa, k.q,
                  c.region, c.error);
      // Softening changes the tangent: compare with perfect plasticity at the same trial.
      if (k.branch == VonMisesBranch::Softening) {
        const FdCheck p = fd_check(perfect, law_of(perfect, s.s0, PointState{}), s.deps);
        EXPECT_LE(p.error, kTol);
        EXPECT_GT((c.tangent - p.tangent).cwiseAbs().maxCoeff(),
                  1e-3 * elastic_stiffness(m.elastic_constants).maxCoeff());
      }
    }
  // Snap-back (G + H_s <= 0): the point drops to c_r at once, the residual tangent.
  const Material snap = von_mises(12 * kPa, 3 * kPa, -5e6);
  const Step s = step_to(snap, Vec3(-40, -50, -75) * kPa, random_rotation(rng, false), rng, false);
  const FdCheck c = fd_check(snap, law_of(snap, s.s0, PointState{}), s.deps);
  EXPECT_EQ(VonMisesBranch(c.region), VonMisesBranch::Residual);
  EXPECT_LE(c.error, kTol);
}
