// Von Mises with linear softening as a const law with the consistent tangent (Acosta §3.2;
// the implicit Newton-Raphson iteration assembles the tangent). The update is von_mises_update (the solver's
// own radial return, run on copies); the tangent is computed beside it.
//
// Tangent. With s^tr the trial deviator, q = sqrt(J2(s^tr)) and the radial return
// sigma = p^tr 1 + beta s^tr, beta = 1 - G dl / q (von_mises.cpp),
//   d sigma / d d_eps = K 1 (x) 1 + 2 G beta P_dev + s^tr (x) d beta / d d_eps,
//   d beta / d d_eps = ((1 - beta) - G d dl/d q) / q  *  d q / d d_eps,   d q / d eps = G s^tr / q,
// where d dl / d q = 1 / (G + H_s) on the softening branch (c = c_p + H_s kappa > c_r) and 1 / G
// on the residual branch (c = c_r) and after a snap-back (G + H_s <= 0). In the Voigt convention
// of law_result.hpp, d q / d deps[j] carries a factor 2 on the shear components.
#pragma once
#include <cstdint>

#include "material/law_result.hpp"
#include "material/von_mises/von_mises.hpp"

namespace skred {

// Which branch of c(kappa) = max(c_r, c_p + H_s kappa) the return ended on.
enum class VonMisesBranch : std::uint8_t { Elastic, Softening, Residual };

// The const law. `branch` (optional) receives the branch of the return.
LawResult von_mises_evaluate(const ElasticConstants& e, const VonMisesParams& vm, const Sym3& stress,
                             const Sym3& deps, const PointState& state, bool want_tangent,
                             VonMisesBranch* branch = nullptr);

}  // namespace skred
