// Parameters of the Mohr-Coulomb and Tresca models (Thesis eq. 5.1-5.4; Paper III §C.3.2).
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

}  // namespace skred
