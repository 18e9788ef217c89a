// Per-material strength parameters for the relative yield function (Post eq. 66), indexed
// like the scenario's material table (Particles::material). Each model gives its strength in
// its folder's info.hpp (Material::strength dispatches).
#pragma once
#include <vector>

#include "material/material.hpp"
#include "material/model_info.hpp"

namespace skred {

// The strength of a material: Mohr-Coulomb {phi, c}, Tresca {0, s_u}, von Mises in plane strain
// {0, peak cohesion}; linear elastic has none (NaN).
inline MaterialStrength strength_of(const Material& m) { return m.strength(); }

inline std::vector<MaterialStrength> material_strengths(const std::vector<Material>& materials) {
  std::vector<MaterialStrength> out;
  out.reserve(materials.size());
  for (const Material& m : materials) out.push_back(strength_of(m));
  return out;
}

}  // namespace skred
