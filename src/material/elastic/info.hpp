// Linear elasticity: name, description and the declared parameters of the elastic block that
// every model has (see material/model_info.hpp).
#pragma once
#include "material/elastic/elastic.hpp"
#include "material/model_info.hpp"

namespace skred {

// The elastic block, common to all models (Thesis eq. 2.5); density is the material's.
inline constexpr ParamSpec kElasticParamSpecs[] = {
    {"density", "kg/m^3", kNoDefault, 1e-3, 1e6, false, false, true, 2000.0, "mass density rho_0"},
    {"young", "Pa", kNoDefault, 1e-3, kMaxStress, false, false, true, 1e+07, "Young's modulus E"},
    {"poisson", "-", kNoDefault, 0.0, 0.5, false, true, true, 0.3, "Poisson's ratio nu, 0 <= nu < 0.5"},
};

inline constexpr ModelInfo kLinearElasticInfo{
    "linear-elastic", "isotropic linear elasticity (Thesis eq. 2.5); never yields", {}};

// No strength: the relative yield function (Post eq. 66) of an elastic material is NaN.
inline MaterialStrength linear_elastic_strength() { return {}; }

}  // namespace skred
