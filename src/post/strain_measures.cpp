#include "post/strain_measures.hpp"

#include <Eigen/Eigenvalues>

namespace skred {

Sym3 engineering_strain(const Mat3& F) {
  // Post eq. 63: eps = (F^T + F)/2 - I.
  return to_voigt(0.5 * (F.transpose() + F) - Mat3::Identity());
}

Sym3 green_lagrange_strain(const Mat3& F) {
  // Post eq. 64: E = (F^T F - I)/2.
  return to_voigt(0.5 * (F.transpose() * F - Mat3::Identity()));
}

Sym3 hencky_strain(const Mat3& F) {
  // Post eq. 65: ln U = sum_i ln(sqrt(lambda_i)) n_i n_i^T, lambda_i, n_i eigenpairs of C.
  // The iterative (QL) solver, not the closed-form computeDirect, keeps small eigenvalues of
  // strongly stretched voxels accurate.
  const Mat3 C = F.transpose() * F;
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(C);
  const Eigen::Vector3d log_stretch = 0.5 * eig.eigenvalues().array().log();
  const Mat3& n = eig.eigenvectors();
  return to_voigt(n * log_stretch.asDiagonal() * n.transpose());
}

}  // namespace skred
