// Parameters of the von Mises model with linear softening (Acosta §3.2).
#pragma once

namespace skred {

// Von Mises with linear softening of the cohesion (Acosta §3.2, after Wang et al.):
// f = sqrt(J2) - c(kappa), c(kappa) = max(c_r, c_p + H_s kappa), kappa = accumulated plastic
// engineering shear strain (PointState::plastic_shear_strain). In plane strain at failure
// sqrt(J2) = (sigma_3 - sigma_1)/2, so this matches Tresca with s_u = c (reference R5).
struct VonMisesParams {
  double cohesion_peak = 0.0;      // c_p [Pa]
  double cohesion_residual = 0.0;  // c_r [Pa], <= c_p
  double softening_modulus = 0.0;  // H_s [Pa per unit plastic shear strain], <= 0
};

}  // namespace skred
