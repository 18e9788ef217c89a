// Strain measures from F (Post eq. 63-65) against closed forms: simple shear, uniaxial
// stretch, rigid rotation, and a stretch seen from rotated axes.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "post/strain_measures.hpp"

using namespace skred;

namespace {

constexpr double kTol = 1e-12;

Mat<2> shear(double g) { return (Mat<2>() << 1.0, g, 0.0, 1.0).finished(); }
Mat<2> rotation(double t) {
  return (Mat<2>() << std::cos(t), -std::sin(t), std::sin(t), std::cos(t)).finished();
}

// Voigt [xx, yy, zz, xy, yz, xz] from the in-plane components.
Sym3 plane(double xx, double yy, double xy) { return (Sym3() << xx, yy, 0, xy, 0, 0).finished(); }

void expect_near(const Sym3& a, const Sym3& b, double tol, const char* what) {
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(a[i], b[i], tol) << what << " component " << i;
}

}  // namespace

TEST(PostStrain, SimpleShearMatchesTextbookForms) {
  for (double g : {1e-3, 0.1, 0.5, 1.0, 2.0, 5.0}) {
    const Mat3 F = deformation3<2>(shear(g));
    // Engineering: eps_xy = g/2 (eq. 63). Green: E_yy = g^2/2, E_xy = g/2 (eq. 64).
    expect_near(engineering_strain(F), plane(0, 0, g / 2), kTol, "engineering");
    expect_near(green_lagrange_strain(F), plane(0, g * g / 2, g / 2), kTol, "green");
    // Hencky (eq. 65): principal stretches s +- g/2, s = sqrt(1 + g^2/4), so
    // ln U = asinh(g/2)/s [[-g/2, 1], [1, g/2]].
    const double s = std::sqrt(1 + g * g / 4), a = std::asinh(g / 2);
    expect_near(hencky_strain(F), plane(-a * g / (2 * s), a * g / (2 * s), a / s), kTol, "hencky");
  }
}

TEST(PostStrain, UniaxialStretchMatchesTextbookForms) {
  for (double l : {0.2, 0.5, 0.999, 1.001, 1.3, 3.0, 10.0}) {
    const Mat3 F = deformation3<2>((Mat<2>() << l, 0, 0, 1).finished());
    expect_near(engineering_strain(F), plane(l - 1, 0, 0), kTol, "engineering");
    expect_near(green_lagrange_strain(F), plane((l * l - 1) / 2, 0, 0), kTol, "green");
    expect_near(hencky_strain(F), plane(std::log(l), 0, 0), kTol, "hencky");
  }
}

TEST(PostStrain, RigidRotationGivesZeroGreenAndHenckyButNotEngineering) {
  for (double deg : {1.0, 10.0, 45.0, 90.0, 150.0}) {
    const double t = deg * std::numbers::pi / 180;
    const Mat3 F = deformation3<2>(rotation(t));
    expect_near(green_lagrange_strain(F), Sym3::Zero(), kTol, "green");
    expect_near(hencky_strain(F), Sym3::Zero(), kTol, "hencky");
    // Eq. 63 is not objective: a rigid rotation shows as eps_xx = eps_yy = cos(t) - 1.
    const Sym3 e = engineering_strain(F);
    expect_near(e, plane(std::cos(t) - 1, std::cos(t) - 1, 0), kTol, "engineering");
    RecordProperty("engineering_error_at_" + std::to_string(static_cast<int>(deg)) + "_deg",
                   fmt::format("{:.6g}", e[0]));
  }
}

TEST(PostStrain, HenckyOfRotatedStretchIsTheStretchInRotatedAxes) {
  // F = R diag(l1, l2, l3): U = diag(l), so ln U = diag(ln l) whatever R is (3D, eq. 65).
  const double l[3] = {0.6, 1.7, 2.5};
  Mat3 R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Mat3 F = R * Eigen::Vector3d(l[0], l[1], l[2]).asDiagonal();
  Sym3 expected = Sym3::Zero();
  for (int i = 0; i < 3; ++i) expected[i] = std::log(l[i]);
  expect_near(hencky_strain(F), expected, kTol, "hencky");
  // And F = diag(l) R: U = R^T diag(l) R.
  const Mat3 G = Mat3(Eigen::Vector3d(l[0], l[1], l[2]).asDiagonal()) * R;
  const Mat3 lnU =
      R.transpose() * Eigen::Vector3d(std::log(l[0]), std::log(l[1]), std::log(l[2])).asDiagonal() * R;
  expect_near(hencky_strain(G), to_voigt(lnU), kTol, "hencky, rotated axes");
}

TEST(PostStrain, MeasuresAgreeForSmallStrains) {
  // All three coincide to first order (Post fig. 17, point C).
  const Mat3 F = deformation3<2>((Mat<2>() << 1.001, 0.0004, -0.0002, 0.9995).finished());
  const Sym3 e = engineering_strain(F), g = green_lagrange_strain(F), h = hencky_strain(F);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(g[i], e[i], 2e-6);
    EXPECT_NEAR(h[i], e[i], 2e-6);
  }
  EXPECT_DOUBLE_EQ(e[2], 0.0);  // plane strain: no out-of-plane strain
}
