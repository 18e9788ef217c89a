// Mohr-Coulomb and Tresca: names, descriptions, declared parameters and strength for the
// relative yield function (see material/model_info.hpp). Keys and ranges as the scenario
// parser checks them; angles are given in degrees in the file and stored in radians.
#pragma once
#include "material/model_info.hpp"
#include "material/mohr_coulomb/params.hpp"

namespace skred {

inline constexpr ParamSpec kMohrCoulombParamSpecs[] = {
    {"friction", "deg", kNoDefault, 0.0, 90.0, false, true, true, 30.0,
     "friction angle phi (Thesis eq. 5.1); friction > 0 or cohesion > 0"},
    {"cohesion", "Pa", kNoDefault, 0.0, kMaxStress, false, false, true, 10000.0,
     "cohesion c (Thesis eq. 5.1)"},
    {"dilation", "deg", 0.0, 0.0, 90.0, false, false, false, 5.0,
     "dilation angle psi of the plastic potential (Thesis eq. 5.4), 0 <= psi <= phi"},
    {"tension_cutoff", "Pa", kInf, 0.0, kMaxStress, false, false, false, 5000.0,
     "Rankine cut-off on the major principal stress (tension positive); none if absent"},
    {"initial_void_ratio", "-", kNoDefault, 0.0, 100.0, true, false, false, 0.6,
     "e0 of the dilation cut-off (Paper III §C.3.2); given together with max_void_ratio"},
    {"max_void_ratio", "-", kNoDefault, 0.0, 100.0, true, false, false, 0.7,
     "e_max > e0: psi = 0 once (1 + e0) exp(eps_v) - 1 >= e_max (Paper III §C.3.2)"},
};

inline constexpr ParamSpec kTrescaParamSpecs[] = {
    {"cohesion", "Pa", kNoDefault, 0.0, kMaxStress, true, false, true, 30000.0,
     "undrained shear strength s_u"},
};

inline constexpr ModelInfo kMohrCoulombInfo{
    "mohr-coulomb",
    "non-associated Mohr-Coulomb, principal-stress return after Clausen et al. (Thesis eq. "
    "5.1-5.4), optional tension and dilation cut-offs",
    kMohrCoulombParamSpecs};

inline constexpr ModelInfo kTrescaInfo{
    "tresca", "Tresca: Mohr-Coulomb with phi = psi = 0 and c = s_u (Thesis eq. 5.1-5.4)", kTrescaParamSpecs};

// Strength for the relative yield function (Post eq. 66): the Mohr-Coulomb envelope itself.
inline MaterialStrength mohr_coulomb_strength(const MohrCoulombParams& p) { return {p.friction, p.cohesion}; }
inline MaterialStrength tresca_strength(const MohrCoulombParams& p) { return {0.0, p.cohesion}; }

}  // namespace skred
