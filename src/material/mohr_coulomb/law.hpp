// Mohr-Coulomb and Tresca as a const law with the consistent tangent (Thesis eq. 5.1-5.4 after
// Clausen et al.; the implicit Newton-Raphson iteration assembles the tangent). The update is
// mohr_coulomb_update (the solver's own return mapping, run on copies); the tangent is computed beside it.
//
// Tangent. The return works on the ordered principal values lambda of the trial stress
// sigma^tr = sigma^k + C : d_eps and keeps the trial's principal directions v_i:
// sigma = sum_i s_i(lambda) v_i v_i^T. In each return region s(lambda) is affine,
//   s = lambda - D B (A^-1 (Aa lambda - k)),  A = Aa D B,
// (Aa: rows a_j of the active yield planes, B: columns b_i of their plastic-potential
// gradients, eq. 5.3-5.4), so its principal-space Jacobian J = ds/dlambda = I - D B A^-1 Aa is
// a constant matrix per region: plane (one plane), compression/extension edge and the Rankine
// plane/edge (two planes), and J = 0 at the apex and every vertex (the returned point is
// fixed). Rotated back with the spin of the principal directions, in the trial's principal
// frame
//   d sigma_ii = sum_j J_ij d sigma^tr_jj,
//   d sigma_ij = (s_i - s_j)/(lambda_i - lambda_j) d sigma^tr_ij  (i != j),
// (the limit (J_ii - J_ij - J_ji + J_jj)/2 for lambda_i = lambda_j), and d sigma^tr = C d_eps.
//
// Dilation cut-off (Paper III §C.3.2): psi switches to 0 when the updated volume strain reaches
// ln((1 + e_max)/(1 + e0)). The tangent is that of the dilation in use for this step; at the
// switch itself the update jumps (it is not differentiable there), as at any region boundary.
#pragma once
#include "material/law_result.hpp"
#include "material/mohr_coulomb/mohr_coulomb.hpp"

namespace skred {

// J = d s / d lambda of the principal return in `region` (see above); the identity for Elastic.
Mat3 mohr_coulomb_principal_tangent(const ElasticConstants& e, const MohrCoulombConstants& k, double sin_psi,
                                    MohrCoulombRegion region);

// d sigma / d sigma^tr (6 x 6, Voigt, tensor shear components) of the isotropic map
// sigma = sum_i s_i v_i v_i^T with principal Jacobian J, trial values `lambda` (ascending) and
// directions `v`, returned values `s`.
Mat6 spectral_tangent(const Vec3& lambda, const Mat3& v, const Vec3& s, const Mat3& J);

// The const law. `region` (optional) receives the return region.
LawResult mohr_coulomb_evaluate(const ElasticConstants& e, const MohrCoulombConstants& k, const Sym3& stress,
                                const Sym3& deps, const PointState& state, bool want_tangent,
                                MohrCoulombRegion* region = nullptr);

}  // namespace skred
