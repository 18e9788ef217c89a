// What a constitutive law returns (deal.II step-42 style: a const law that gives the stress and,
// on request, the tangent; cb-geo style: all material math in 3D Voigt form, also in 2D).
//
// Voigt convention of the tangent. Stress and strain are Sym3 in the order
// [xx, yy, zz, xy, yz, xz] with TENSOR shear components (eps_xy, not gamma_xy = 2 eps_xy), as
// everywhere in skred. The tangent is the plain partial derivative of that vector by that vector,
//   tangent(i, j) = d sigma[i] / d deps[j],
// where a change of deps[j], j >= 3, changes both eps_ij and eps_ji of the symmetric tensor.
// So d_sigma = tangent * d_deps for Sym3 increments, and the elastic tangent has 2G (not G) on
// the shear diagonal. For engineering shear strains (gamma = 2 eps, the B-matrix convention of
// Acosta eq. 5 and 11) use tangent * diag(1, 1, 1, 1/2, 1/2, 1/2); the finite-difference tests
// (tests/test_material_tangent.cpp) perturb deps[j] in exactly the convention above. In plane
// strain the in-plane tangent is the block of rows and columns {0, 1, 3} (xx, yy, xy); row 2
// gives d sigma_zz, and columns 2, 4, 5 (out-of-plane strains) are not used.
//
// The tangent is the consistent (algorithmic) one: the exact derivative of the discrete update
// sigma^{k+1}(sigma^k, d_eps, state) by d_eps, which the implicit integrator's Newton-Raphson
// iteration assembles (src/implicit). Acosta's own iteration (eq. 5 and 10-11) uses the
// elastic D_p instead and re-applies the out-of-balance force; skred offers both
// (implicit.iteration). It is defined where the update is differentiable, i.e. away from the
// boundaries between return regions.
#pragma once
#include "core/types.hpp"
#include "material/state.hpp"

namespace skred {

using Mat6 = Eigen::Matrix<double, 6, 6>;

struct LawResult {
  Sym3 stress = Sym3::Zero();          // sigma^{k+1} (before any push-forward by the solver)
  PointState state;                    // the updated state
  Sym3 plastic_strain = Sym3::Zero();  // d_eps_p of this step (tensor components)
  Mat6 tangent = Mat6::Zero();         // d sigma^{k+1} / d d_eps, see above; if has_tangent
  bool has_tangent = false;
};

}  // namespace skred
