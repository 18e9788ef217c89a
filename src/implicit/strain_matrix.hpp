// The strain-displacement matrix B of one node of a point's stencil (Acosta eq. 5, 11 and, in
// axisymmetric geometry, App. A1 eq. 32), in skred's Voigt order [xx, yy, zz, xy, yz, xz] with
// tensor shear components (material/law_result.hpp): d_eps = sum_i B_i du_i.
//
// With tensor shear, sigma : d_eps = sigma^T W d_eps, W = diag(1, 1, 1, 2, 2, 2), so the
// internal force of a point on node i is f_i = V B_i^T W sigma (eq. 4) and its stiffness
// K_ij = V B_i^T W T B_j with T = d sigma / d d_eps, the laws' tangent (eq. 5, 10).
//
// Axisymmetric (x the radius r, y the axis): the hoop strain is u_r / r (eq. 32; the seed prints
// its row of B as N_i / r on the radial displacement, which is what is built here), taken at the
// point's radius, and V is the volume per radian (r dA, eq. 29-31).
#pragma once
#include "core/types.hpp"

namespace skred {

template <int D>
using StrainMatrix = Eigen::Matrix<double, 6, D>;

// B_i of a node with weight N and gradient dN; inv_r = 1 / r_p in axisymmetric geometry, else 0.
template <int D>
inline StrainMatrix<D> strain_matrix(double N, const Vec<D>& dN, double inv_r) {
  StrainMatrix<D> B = StrainMatrix<D>::Zero();
  B(0, 0) = dN[0];
  B(1, 1) = dN[1];
  B(3, 0) = 0.5 * dN[1];
  B(3, 1) = 0.5 * dN[0];
  if constexpr (D == 3) {
    B(2, 2) = dN[2];
    B(4, 1) = 0.5 * dN[2];
    B(4, 2) = 0.5 * dN[1];
    B(5, 0) = 0.5 * dN[2];
    B(5, 2) = 0.5 * dN[0];
  } else {
    B(2, 0) = N * inv_r;  // hoop strain u_r / r (zero in plane strain)
  }
  return B;
}

// The Voigt weights of the tensor shear components: W sigma.
inline Sym3 voigt_weighted(const Sym3& s) {
  Sym3 w = s;
  w.tail<3>() *= 2.0;
  return w;
}

}  // namespace skred
