// Isotropic linear elasticity in 3D Voigt form (plane strain is the 2D case with
// zero out-of-plane strain; the out-of-plane stress follows from it).
#pragma once
#include "core/inline.hpp"
#include "core/types.hpp"

namespace skred {

struct ElasticParams {
  double young = 0.0;    // E [Pa]
  double poisson = 0.0;  // nu [-]

  double shear_modulus() const { return young / (2.0 * (1.0 + poisson)); }
  double bulk_modulus() const { return young / (3.0 * (1.0 - 2.0 * poisson)); }
  double lame_lambda() const { return young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)); }
  // Constrained (oedometric, P-wave) modulus M = E (1 - nu) / ((1 + nu)(1 - 2 nu)).
  double constrained_modulus() const { return lame_lambda() + 2.0 * shear_modulus(); }
};

// Lame constants, computed once per material so the time loop does no divisions.
struct ElasticConstants {
  double lambda = 0.0, two_g = 0.0;
  ElasticConstants() = default;
  explicit ElasticConstants(const ElasticParams& e)
      : lambda(e.lame_lambda()), two_g(2.0 * e.shear_modulus()) {}
};

// d_sigma = C : d_eps (Thesis eq. 2.5); strain in tensor components. Formed component by
// component: 2G d_eps as a vector with its normal components patched after it left them in
// memory in halves, which the next read of the whole waited for (a store-forwarding stall).
SKRED_INLINE Sym3 elastic_increment(const ElasticConstants& e, const Sym3& deps) {
  const double two_g = e.two_g, lt = e.lambda * (deps[0] + deps[1] + deps[2]);
  Sym3 ds;
  ds << two_g * deps[0] + lt, two_g * deps[1] + lt, two_g * deps[2] + lt, two_g * deps[3], two_g * deps[4],
      two_g * deps[5];
  return ds;
}

}  // namespace skred
