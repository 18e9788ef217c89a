// Parameters of the plastic soil models (Thesis eq. 5.1-5.4; Paper III §C.3.2; Acosta §3.2).
// Angles are stored in radians; the scenario file gives degrees.
#pragma once
#include <cmath>
#include <limits>

namespace skred {

// Mohr-Coulomb, non-associated (Thesis eq. 5.1 yield function, eq. 5.4 plastic potential).
// Tresca is the case friction = dilation = 0 with cohesion = undrained strength s_u.
struct MohrCoulombParams {
  double friction = 0.0;  // phi [rad]
  double cohesion = 0.0;  // c [Pa]
  double dilation = 0.0;  // psi [rad], 0 <= psi <= phi
  // Largest allowed principal stress (tension positive) [Pa]; +inf = no tension cut-off.
  // Values above the apex stress c cot(phi) have no effect.
  double tension_cutoff = std::numeric_limits<double>::infinity();
  // Dilation cut-off (Paper III §C.3.2): once the void ratio e = (1 + e0) exp(eps_v) - 1
  // reaches max_void_ratio the point flows with psi = 0. max_void_ratio <= 0 disables it.
  double initial_void_ratio = 0.0;  // e0 [-]
  double max_void_ratio = 0.0;      // e_max [-]
};

// Von Mises with linear softening of the cohesion (Acosta §3.2, after Wang et al.):
// f = sqrt(J2) - c(kappa), c(kappa) = max(c_r, c_p + H_s kappa), kappa = accumulated plastic
// engineering shear strain (PointState::plastic_shear_strain). In plane strain at failure
// sqrt(J2) = (sigma_3 - sigma_1)/2, so this matches Tresca with s_u = c (reference R5).
struct VonMisesParams {
  double cohesion_peak = 0.0;       // c_p [Pa]
  double cohesion_residual = 0.0;   // c_r [Pa], <= c_p
  double softening_modulus = 0.0;   // H_s [Pa per unit plastic shear strain], <= 0
};

}  // namespace skred
