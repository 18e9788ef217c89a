// Total strain measures computed from the deformation gradient F (Post §7.3). They are
// post-processing only: the time step never uses them. Every function takes the 3D F; a 2D
// (plane-strain) F is embedded first with deformation3(), which puts F_zz = 1.
// Results are symmetric tensors in Voigt order [xx, yy, zz, xy, yz, xz] with tensor (not
// engineering) shear components, like the stresses.
#pragma once
#include "core/types.hpp"

namespace skred {

// The 3D deformation gradient of a D-dimensional one (plane strain: F_zz = 1, no coupling).
template <int D>
inline Mat3 deformation3(const Mat<D>& F) {
  return embed3<D>(F, 1.0);
}

// Engineering (small) strain eps = (F^T + F)/2 - I (Post eq. 63). Not objective: a rigid
// rotation by theta gives eps_xx = eps_yy = cos(theta) - 1 instead of 0.
Sym3 engineering_strain(const Mat3& F);

// Green-Lagrange strain E = (F^T F - I)/2 (Post eq. 64).
Sym3 green_lagrange_strain(const Mat3& F);

// Hencky (logarithmic) strain E_ln = ln U with U = (F^T F)^(1/2) (Post eq. 65), computed from
// the eigen-decomposition C = F^T F = sum lambda_i n_i n_i^T as sum (ln lambda_i / 2) n_i n_i^T.
// F must be invertible (det F != 0); otherwise the result contains -inf or NaN.
Sym3 hencky_strain(const Mat3& F);

}  // namespace skred
