#include "post/invariants.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace skred {

PrincipalStresses principal_stresses(const Sym3& s) {
  double v[3];
  if (s[4] == 0.0 && s[5] == 0.0) {
    // Post eq. 59 in the plane, the out-of-plane stress as the third principal stress.
    const double c = 0.5 * (s[0] + s[1]);
    const double r = std::hypot(0.5 * (s[0] - s[1]), s[3]);
    v[0] = c - r;
    v[1] = c + r;
    v[2] = s[2];
  } else {
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(to_matrix(s), Eigen::EigenvaluesOnly);
    for (int i = 0; i < 3; ++i) v[i] = eig.eigenvalues()[i];
  }
  std::sort(v, v + 3);
  return {v[0], v[1], v[2]};
}

double principal_angle_degrees(const Sym3& s) {
  // Post eq. 60 (see the header): tan 2 theta = 2 xy / (xx - yy).
  const double theta = 0.5 * std::atan2(2.0 * s[3], s[0] - s[1]);
  const double deg = theta * 180.0 / std::numbers::pi;
  return deg == -90.0 ? 90.0 : deg;  // atan2(-0, negative) = -pi: keep (-90, 90]
}

double mean_stress_p(const PrincipalStresses& ps) { return (ps.s1 + ps.s2 + ps.s3) / 3.0; }

double deviatoric_stress_q(const PrincipalStresses& ps) {
  const double a = ps.s1 - ps.s2, b = ps.s2 - ps.s3, c = ps.s1 - ps.s3;
  return std::sqrt(0.5 * (a * a + b * b + c * c));
}

double relative_yield(const Sym3& s, double friction, double cohesion) {
  if (std::isnan(friction) || std::isnan(cohesion)) return std::numeric_limits<double>::quiet_NaN();
  const PrincipalStresses ps = principal_stresses(s);
  // Post eq. 66 with eq. 45's sin(phi): radius over available radius at the same centre.
  const double radius = 0.5 * (ps.s3 - ps.s1);
  const double available = cohesion * std::cos(friction) - 0.5 * (ps.s1 + ps.s3) * std::sin(friction);
  if (available <= 0.0) return std::numeric_limits<double>::infinity();
  return radius / available;
}

}  // namespace skred
