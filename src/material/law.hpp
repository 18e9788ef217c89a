// The constitutive law of a material as a const function (style guide: deal.II step-42's
// const law returning stress and tangent; cb-geo's 3D Voigt material math):
//   (sigma^k, d_eps, state) -> (sigma^{k+1}, state^{k+1}, d_eps_p, optionally the consistent
//   tangent d sigma^{k+1} / d d_eps),
// with all inputs by const reference. The update is the model's own in-place return mapping
// (the one the explicit solver inlines through update_stress), run on copies, so there is one
// implementation of each return; the tangent is computed beside it in the model's folder.
// The Voigt convention of the tangent is documented in material/law_result.hpp. The implicit
// integrator's Newton-Raphson iteration assembles K from this tangent (Acosta eq. 5 and 10-11
// with D_p replaced by it; the seed's own iteration keeps the elastic D_p).
#pragma once
#include "material/elastic/law.hpp"
#include "material/law_result.hpp"
#include "material/material.hpp"
#include "material/mohr_coulomb/law.hpp"
#include "material/von_mises/law.hpp"

namespace skred {

inline LawResult evaluate(const Material& m, const Sym3& stress, const Sym3& deps, const PointState& state,
                          bool want_tangent) {
  switch (m.model) {
    case Model::LinearElastic:
      return elastic_evaluate(m.elastic_constants, stress, deps, state, want_tangent);
    case Model::MohrCoulomb:
    case Model::Tresca:
      return mohr_coulomb_evaluate(m.elastic_constants, m.mohr_coulomb_constants, stress, deps, state,
                                   want_tangent);
    case Model::VonMises:
      return von_mises_evaluate(m.elastic_constants, m.von_mises, stress, deps, state, want_tangent);
  }
  return {};
}

}  // namespace skred
