// Consistent tangent of the Mohr-Coulomb return (see law.hpp for the derivation).
#include "material/mohr_coulomb/law.hpp"

#include "material/elastic/law.hpp"

namespace skred {

namespace {

using R = MohrCoulombRegion;

// The yield planes of mohr_coulomb.cpp: gradient a of f (eq. 5.1) and b of g (eq. 5.4) for
// 0 (the plane), 1 (across the compression edge), 2 (across the extension edge), and the
// Rankine planes 3, 4 (sigma_3 = t, sigma_2 = t; associated).
void plane_gradients(int i, double sin_phi, double sin_psi, Vec3& a, Vec3& b) {
  const double sp = sin_phi, sq = sin_psi;
  switch (i) {
    case 0:
      a = Vec3(-(1 - sp), 0, 1 + sp) * 0.5;
      b = Vec3(-(1 - sq), 0, 1 + sq) * 0.5;
      return;
    case 1:
      a = Vec3(-(1 - sp), 1 + sp, 0) * 0.5;
      b = Vec3(-(1 - sq), 1 + sq, 0) * 0.5;
      return;
    case 2:
      a = Vec3(0, -(1 - sp), 1 + sp) * 0.5;
      b = Vec3(0, -(1 - sq), 1 + sq) * 0.5;
      return;
    default: a = b = Vec3::Unit(5 - i); return;
  }
}

}  // namespace

Mat3 mohr_coulomb_principal_tangent(const ElasticConstants& e, const MohrCoulombConstants& k, double sin_psi,
                                    MohrCoulombRegion region) {
  int planes[2], n = 0;
  switch (region) {
    case R::Elastic: return Mat3::Identity();
    case R::Plane:
      planes[0] = 0;
      n = 1;
      break;
    case R::Tension:
      planes[0] = 3;
      n = 1;
      break;
    case R::CompressionEdge:
      planes[0] = 0;
      planes[1] = 1;
      n = 2;
      break;
    case R::ExtensionEdge:
      planes[0] = 0;
      planes[1] = 2;
      n = 2;
      break;
    case R::PlaneTension:
      planes[0] = 0;
      planes[1] = 3;
      n = 2;
      break;
    case R::TensionEdge:
      planes[0] = 3;
      planes[1] = 4;
      n = 2;
      break;
    // Apex, tension apex and the corners: the returned point is a fixed vertex.
    case R::Apex:
    case R::TensionApex:
    case R::ExtensionCorner:
    case R::CompressionCorner: return Mat3::Zero();
  }
  // D = lambda 1 1^T + 2G I, the principal-space elastic stiffness.
  const Mat3 D = Mat3::Constant(e.lambda) + e.two_g * Mat3::Identity();
  Eigen::Matrix<double, 3, 2> B = Eigen::Matrix<double, 3, 2>::Zero();  // columns b_i
  Eigen::Matrix<double, 3, 2> Aa = B;  // columns a_j (the transpose of Aa in law.hpp)
  for (int m = 0; m < n; ++m) {
    Vec3 a, b;
    plane_gradients(planes[m], k.sin_phi, sin_psi, a, b);
    Aa.col(m) = a;
    B.col(m) = b;
  }
  if (n == 1) {
    const Vec3 Db = D * B.col(0);
    return Mat3::Identity() - Db * Aa.col(0).transpose() / Aa.col(0).dot(Db);
  }
  const Eigen::Matrix<double, 3, 2> DB = D * B;
  const Eigen::Matrix2d A = Aa.transpose() * DB;  // A_ji = a_j . D b_i
  return Mat3::Identity() - DB * A.inverse() * Aa.transpose();
}

Mat6 spectral_tangent(const Vec3& lambda, const Mat3& v, const Vec3& s, const Mat3& J) {
  // Spin factors omega_ij = (s_i - s_j)/(lambda_i - lambda_j), or the limit for equal values.
  const double scale = lambda.cwiseAbs().maxCoeff();
  Mat3 omega = Mat3::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (i == j) continue;
      const double dl = lambda[i] - lambda[j];
      omega(i, j) =
          std::abs(dl) > 1e-10 * scale ? (s[i] - s[j]) / dl : 0.5 * (J(i, i) - J(i, j) - J(j, i) + J(j, j));
    }
  Mat6 T;
  for (int c = 0; c < 6; ++c) {
    const Mat3 Bp = v.transpose() * to_matrix(Sym3::Unit(c)) * v;  // d sigma^tr in the frame
    Mat3 A = omega.cwiseProduct(Bp);
    A.diagonal() = J * Bp.diagonal();
    T.col(c) = to_voigt(v * A * v.transpose());
  }
  return T;
}

LawResult mohr_coulomb_evaluate(const ElasticConstants& e, const MohrCoulombConstants& k, const Sym3& stress,
                                const Sym3& deps, const PointState& state, bool want_tangent,
                                MohrCoulombRegion* region) {
  LawResult r;
  r.stress = stress;
  r.state = state;
  MohrCoulombRegion reg = MohrCoulombRegion::Elastic;
  r.plastic_strain = mohr_coulomb_update(e, k, r.stress, deps, r.state, &reg);
  if (region) *region = reg;
  if (!want_tangent) return r;
  const Mat6 C = elastic_stiffness(e);
  r.has_tangent = true;
  if (reg == MohrCoulombRegion::Elastic) {
    r.tangent = C;
    return r;
  }
  // The same trial and dilation as the update (eq. 5.2; Paper III §C.3.2).
  const Principal pd = principal_decomposition(stress + elastic_increment(e, deps));
  const double sin_psi = r.state.volume_strain >= k.max_volume_strain ? 0.0 : k.sin_psi;
  const Mat3 rs = pd.vectors.transpose() * to_matrix(r.stress) * pd.vectors;
  const Mat3 J = mohr_coulomb_principal_tangent(e, k, sin_psi, reg);
  r.tangent = spectral_tangent(pd.values, pd.vectors, rs.diagonal(), J) * C;
  return r;
}

}  // namespace skred
