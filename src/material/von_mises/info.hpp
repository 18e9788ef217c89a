// Von Mises with linear softening: name, description, declared parameters and strength for
// the relative yield function (see material/model_info.hpp). Keys and ranges as the scenario
// parser checks them.
#pragma once
#include "material/model_info.hpp"
#include "material/von_mises/params.hpp"

namespace skred {

inline constexpr ParamSpec kVonMisesParamSpecs[] = {
    {"cohesion", "Pa", kNoDefault, 0.0, kMaxStress, true, false, true, 10000.0,
     "peak cohesion c_p: f = sqrt(J2) - c(kappa) (Acosta §3.2)"},
    {"residual_cohesion", "Pa", kNoDefault, 0.0, kMaxStress, false, false, false, 3000.0,
     "residual cohesion c_r, 0 <= c_r <= c_p; defaults to c_p (no softening)"},
    {"softening_modulus", "Pa", 0.0, -kMaxStress, 0.0, false, false, false, -30000.0,
     "H_s <= 0 in c(kappa) = max(c_r, c_p + H_s kappa), kappa = plastic shear strain"},
};

inline constexpr ModelInfo kVonMisesInfo{
    "von-mises", "von Mises with linear post-peak softening of the cohesion, radial return (Acosta §3.2)",
    kVonMisesParamSpecs};

// Strength for the relative yield function (Post eq. 66): in plane strain sqrt(J2) = c is the
// Tresca envelope phi = 0 with the peak cohesion (reference R5).
inline MaterialStrength von_mises_strength(const VonMisesParams& p) { return {0.0, p.cohesion_peak}; }

}  // namespace skred
