// Per-material strength parameters for the relative yield function (Post eq. 66), indexed
// like the scenario's material table (Particles::material).
#pragma once
#include <limits>
#include <vector>

#include "material/material.hpp"

namespace skred {

// Mohr-Coulomb strength: friction angle phi [rad] and cohesion c [Pa]. Both NaN for a material
// without a strength (linear elastic), whose relative yield is then written as NaN.
struct MaterialStrength {
  double friction = std::numeric_limits<double>::quiet_NaN();
  double cohesion = std::numeric_limits<double>::quiet_NaN();
};

// The strength of each material. Linear elastic has none. A plastic model adds its case here:
// Mohr-Coulomb {phi, c}, Tresca {0, s_u}; von Mises in plane strain {0, current cohesion}.
inline MaterialStrength strength_of(const Material& m) {
  if (!m.plastic()) return {};
  return {m.friction_angle(), m.strength_cohesion()};
}

inline std::vector<MaterialStrength> material_strengths(const std::vector<Material>& materials) {
  std::vector<MaterialStrength> out;
  out.reserve(materials.size());
  for (const Material& m : materials) out.push_back(strength_of(m));
  return out;
}

}  // namespace skred
