// The stress update of one material point from a grid velocity gradient.
#pragma once
#include <cmath>
#include "core/inline.hpp"

#include "core/types.hpp"
#include "material/material.hpp"
#include "solver/kinematics_3d.hpp"

namespace skred {

// The end of a plane-strain update, after the material's return (eq. 4.4, 3.2, Post eq.
// 72-73, 4.16): dt grad v = [g00 g01; g10 g11], sigma^k = (o0, o1, o2, o3), d_eps_p =
// (p0, p1, p2, p3); `stress` holds the unrotated update S^{k+1}. Inlined once per material
// branch; Plastic = false (d_eps_p = 0) drops the plastic terms.
template <bool Plastic>
SKRED_INLINE StressUpdateResult finish_plane_kinematics(double g00, double g01, double g10, double g11,
                                                        double o0, double o1, double o2, double o3, double p0,
                                                        double p1, double p2, double p3, double volume0,
                                                        const PointStress<2>& stress, Mat<2>& F, Mat<2>& Fe);

// Push-forward sigma = dF S dF^T / det dF (eq. 4.4) of plane-strain stress components in place.
SKRED_INLINE void push_forward_plane(double g00, double g01, double g10, double g11, double inv_J, double& s0,
                                     double& s1, double& s2, double& s3) {
  const double a00 = 1.0 + g00, a11 = 1.0 + g11;
  const double b00 = a00 * s0 + g01 * s3, b01 = a00 * s3 + g01 * s1;  // dF S
  const double b10 = g10 * s0 + a11 * s3, b11 = g10 * s3 + a11 * s1;
  s0 = (b00 * a00 + b01 * g01) * inv_J;
  s1 = (b10 * g10 + b11 * a11) * inv_J;
  s2 *= inv_J;
  s3 = 0.5 * ((b00 * g10 + b01 * a11) + (b10 * a00 + b11 * g01)) * inv_J;
}

template <bool Plastic>
SKRED_INLINE StressUpdateResult finish_plane_update(double g00, double g01, double g10, double g11, double o0,
                                                    double o1, double o2, double o3, double p0, double p1,
                                                    double p2, double p3, double volume0,
                                                    PointStress<2>& stress, Mat<2>& F, Mat<2>& Fe) {
  const double inv_J = 1.0 / ((1.0 + g00) * (1.0 + g11) - g01 * g10);
  push_forward_plane(g00, g01, g10, g11, inv_J, stress[0], stress[1], stress[2], stress[3]);
  return finish_plane_kinematics<Plastic>(g00, g01, g10, g11, o0, o1, o2, o3, p0, p1, p2, p3, volume0, stress,
                                          F, Fe);
}

// F <- dF F (eq. 3.2), Fe <- (I + d_eps_e) Fe (Post eq. 72-73), the volume and the trapezoidal
// stress work (eq. 4.16), given the updated stress.
template <bool Plastic>
SKRED_INLINE StressUpdateResult finish_plane_kinematics(double g00, double g01, double g10, double g11,
                                                        double o0, double o1, double o2, double o3, double p0,
                                                        double p1, double p2, double p3, double volume0,
                                                        const PointStress<2>& stress, Mat<2>& F, Mat<2>& Fe) {
  const double e0 = g00, e1 = g11, e3 = 0.5 * (g01 + g10);
  const double a00 = 1.0 + g00, a11 = 1.0 + g11;
  // F <- dF F (eq. 3.2) and Fe <- (I + d_eps_e) Fe (Post eq. 72-73).
  const double f00 = F(0, 0), f01 = F(0, 1), f10 = F(1, 0), f11 = F(1, 1);
  F(0, 0) = a00 * f00 + g01 * f10;
  F(0, 1) = a00 * f01 + g01 * f11;
  F(1, 0) = g10 * f00 + a11 * f10;
  F(1, 1) = g10 * f01 + a11 * f11;
  const double c00 = 1.0 + e0 - p0, c11 = 1.0 + e1 - p1, c01 = e3 - p3;
  const double h00 = Fe(0, 0), h01 = Fe(0, 1), h10 = Fe(1, 0), h11 = Fe(1, 1);
  Fe(0, 0) = c00 * h00 + c01 * h10;
  Fe(0, 1) = c00 * h01 + c01 * h11;
  Fe(1, 0) = c01 * h00 + c11 * h10;
  Fe(1, 1) = c01 * h01 + c11 * h11;
  const double volume = volume0 * (F(0, 0) * F(1, 1) - F(0, 1) * F(1, 0));
  // Trapezoidal work (eq. 4.16) split into stored and dissipated parts.
  const double m0 = o0 + stress[0], m1 = o1 + stress[1], m2 = o2 + stress[2], m3 = o3 + stress[3];
  const double half_v = 0.5 * volume;
  const double total = m0 * e0 + m1 * e1 + 2.0 * m3 * e3;
  if constexpr (!Plastic) return {half_v * total, 0.0, volume};
  const double plastic = m0 * p0 + m1 * p1 + m2 * p2 + 2.0 * m3 * p3;
  return {half_v * (total - plastic), half_v * plastic, volume};
}

// Kirchhoff stress of the isotropic hyperelastic law with the stored energy per reference
// volume W = G sum (l_i - 1)^2 + lambda/2 (sum (l_i - 1))^2 of the principal stretches l_i
// (the Biot strain U - I in place of the small strain of Thesis eq. 2.5, which it is at small
// strain): tau = 2G (V - I) V + lambda tr(V - I) V with the left stretch V = sqrt(F F^T). In
// uniaxial strain its Cauchy stress is exactly E (l - 1). Plane strain (V_zz = 1): (xx, yy,
// zz, xy), with the 2 x 2 square root in closed form, V = (B + J I) / sqrt(tr B + 2J).
SKRED_INLINE Eigen::Vector4d biot_kirchhoff_plane(const Mat<2>& F, double lambda, double two_g) {
  const double b00 = F(0, 0) * F(0, 0) + F(0, 1) * F(0, 1), b11 = F(1, 0) * F(1, 0) + F(1, 1) * F(1, 1);
  const double b01 = F(0, 0) * F(1, 0) + F(0, 1) * F(1, 1);
  const double J = F(0, 0) * F(1, 1) - F(0, 1) * F(1, 0), inv_t = 1.0 / std::sqrt(b00 + b11 + 2.0 * J);
  const double v00 = (b00 + J) * inv_t, v11 = (b11 + J) * inv_t, v01 = b01 * inv_t;  // V
  const double lt = lambda * (v00 + v11 - 2.0);                                      // lambda tr(V - I)
  return {two_g * (b00 - v00) + lt * v00, two_g * (b11 - v11) + lt * v11, lt, two_g * (b01 - v01) + lt * v01};
}

template <int D>
inline Sym3 biot_kirchhoff(const Mat<D>& F, double lambda, double two_g) {
  if constexpr (D == 2) {
    const Eigen::Vector4d t = biot_kirchhoff_plane(F, lambda, two_g);
    Sym3 out;
    out << t[0], t[1], t[2], t[3], 0.0, 0.0;
    return out;
  } else {
    const Mat3 B = F * F.transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> es(B);
    const Mat3 V =
        es.eigenvectors() * es.eigenvalues().cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
    const Mat3 tau = two_g * (B - V) + lambda * (V.trace() - 3.0) * V;
    return to_voigt(tau);
  }
}

// Objective stress update through the deformation-gradient increment (Thesis eq. 4.1-4.4):
// d_eps = dt sym(grad v) (eq. 2.20), S^{k+1} = sigma^k + C : d_eps and the plastic return
// (eq. 4.2-4.3, 5.2-5.4, done by the material), sigma^{k+1} = dF S dF^T / det dF with
// dF = I + dt grad v (eq. 3.5, 4.4), and F <- dF F (eq. 3.2). `Fe` is the elastic part of F,
// updated by Fe <- (I + d_eps - d_eps_p) Fe (Post eq. 72-73). The trapezoidal stress work
// splits exactly into the stored (elastic) part and the plastic dissipation.
template <int D>
SKRED_INLINE StressUpdateResult update_point_stress(const Material& mat, const Mat<D>& grad_v, double dt,
                                                    double volume0, PointStress<D>& stress, PointState& state,
                                                    Mat<D>& F, Mat<D>& Fe) {
  if constexpr (D == 2) {
    // Plane strain written out in scalars: this runs twice per point and step.
    const double g00 = dt * grad_v(0, 0), g01 = dt * grad_v(0, 1);
    const double g10 = dt * grad_v(1, 0), g11 = dt * grad_v(1, 1);
    const double e0 = g00, e1 = g11, e3 = 0.5 * (g01 + g10);  // d_eps (eq. 2.20)
    const double o0 = stress[0], o1 = stress[1], o2 = stress[2], o3 = stress[3];
    double p0 = 0.0, p1 = 0.0, p2 = 0.0, p3 = 0.0;                 // d_eps_p
    if (mat.model == Model::LinearElastic && !mat.hyperelastic) {  // eq. 2.5
      const double tr = e0 + e1, lam = mat.elastic_constants.lambda * tr;
      const double two_g = mat.elastic_constants.two_g;
      stress[0] = o0 + lam + two_g * e0;
      stress[1] = o1 + lam + two_g * e1;
      stress[2] = o2 + lam;
      stress[3] = o3 + two_g * e3;  // the state is untouched (see update_stress)
      return finish_plane_update<false>(g00, g01, g10, g11, o0, o1, o2, o3, 0.0, 0.0, 0.0, 0.0, volume0,
                                        stress, F, Fe);
    } else if (mat.model == Model::LinearElastic) {  // hyperelastic (biot_kirchhoff)
      // tau^{k+1} = dF (tau^k - tau_H(F^k)) dF^T + tau_H(F^{k+1}) (tau = J sigma): the stress of
      // the hyperelastic law of F, plus whatever stress the point had besides it (an initial
      // stress, a stage's carried stress) convected as in eq. 4.4. An elastic step therefore
      // stores exactly the energy of F and gives it back (an incremental update
      // sigma^k + C : d_eps pushed forward does not: R3 created 5 % energy at its 25 % strains).
      const double lam = mat.elastic_constants.lambda, two_g = mat.elastic_constants.two_g;
      const double J0 = F(0, 0) * F(1, 1) - F(0, 1) * F(1, 0);
      const Eigen::Vector4d t0 = biot_kirchhoff_plane(F, lam, two_g);
      double s0 = J0 * o0 - t0[0], s1 = J0 * o1 - t0[1], s2 = J0 * o2 - t0[2], s3 = J0 * o3 - t0[3];
      push_forward_plane(g00, g01, g10, g11, 1.0, s0, s1, s2, s3);
      Mat<2> F1;
      F1 << (1.0 + g00) * F(0, 0) + g01 * F(1, 0), (1.0 + g00) * F(0, 1) + g01 * F(1, 1),
          g10 * F(0, 0) + (1.0 + g11) * F(1, 0), g10 * F(0, 1) + (1.0 + g11) * F(1, 1);
      const Eigen::Vector4d t1 = biot_kirchhoff_plane(F1, lam, two_g);
      const double inv_J1 = 1.0 / (F1(0, 0) * F1(1, 1) - F1(0, 1) * F1(1, 0));
      stress[0] = (s0 + t1[0]) * inv_J1;
      stress[1] = (s1 + t1[1]) * inv_J1;
      stress[2] = (s2 + t1[2]) * inv_J1;
      stress[3] = (s3 + t1[3]) * inv_J1;  // the state is untouched (see update_stress)
      return finish_plane_kinematics<false>(g00, g01, g10, g11, o0, o1, o2, o3, 0.0, 0.0, 0.0, 0.0, volume0,
                                            stress, F, Fe);
    } else if (mat.model == Model::MohrCoulomb || mat.model == Model::Tresca) {
      const Eigen::Vector4d dp = mohr_coulomb_update_plane(mat.elastic_constants, mat.mohr_coulomb_constants,
                                                           stress, e0, e1, e3, state);
      p0 = dp[0];
      p1 = dp[1];
      p2 = dp[2];
      p3 = dp[3];
    } else {  // von Mises, through the general interface
      Sym3 deps, full = full_stress<2>(stress);
      deps << e0, e1, 0.0, e3, 0.0, 0.0;
      const Sym3 dp = update_stress(mat, full, deps, state);
      stress = full.head<4>();
      p0 = dp[0];
      p1 = dp[1];
      p2 = dp[2];
      p3 = dp[3];
    }
    return finish_plane_update<true>(g00, g01, g10, g11, o0, o1, o2, o3, p0, p1, p2, p3, volume0, stress, F,
                                     Fe);
  } else {
    // 3D in scalars (kinematics_3d.hpp), the same steps as the plane-strain branch.
    double g[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) g[i][j] = dt * grad_v(i, j);
    const Sym3 deps = kinematics3::strain_increment(g);
    const Sym3 old = stress;
    if (mat.model == Model::LinearElastic && !mat.hyperelastic) {  // eq. 2.5
      stress += elastic_increment(mat.elastic_constants, deps);
      kinematics3::push_forward(g, stress);
      return kinematics3::finish<false>(g, deps, deps, old, volume0, stress, F, Fe);
    } else if (mat.model == Model::LinearElastic) {  // hyperelastic, as in plane strain above
      const double lam = mat.elastic_constants.lambda, two_g = mat.elastic_constants.two_g;
      const Mat<D> dF = Mat<D>::Identity() + dt * grad_v;
      const Sym3 rest = F.determinant() * stress - biot_kirchhoff<D>(F, lam, two_g);
      const Mat<D> F1 = dF * F;
      stress = (to_voigt(dF * to_matrix(rest) * dF.transpose()) + biot_kirchhoff<D>(F1, lam, two_g)) /
               F1.determinant();
      return kinematics3::finish<false>(g, deps, deps, old, volume0, stress, F, Fe);
    }
    const Sym3 deps_p = update_stress(mat, stress, deps, state);
    kinematics3::push_forward(g, stress);
    return kinematics3::finish<true>(g, deps, deps_p, old, volume0, stress, F, Fe);
  }
}

}  // namespace skred
