// Reference helpers of the plasticity tests, independent of the code under test: Hooke's law and
// an eigen-system written out with Eigen's own solver, rotated frames, and a Mohr-Coulomb case.
#pragma once
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <limits>
#include <numbers>

#include "material/mohr_coulomb.hpp"

namespace skred::plasticity_test {

inline constexpr double kPa = 1e3;
inline constexpr double deg = std::numbers::pi / 180.0;

// ---------------------------------------------------------------------------------------------
// Reference helpers (independent of the code under test)

struct Elastic {
  double E, nu;
  double G() const { return E / (2 * (1 + nu)); }
  double lambda() const { return E * nu / ((1 + nu) * (1 - 2 * nu)); }
  ElasticConstants constants() const { return ElasticConstants(ElasticParams{E, nu}); }
};

// The soil of the Mohr-Coulomb tests.
inline const Elastic kSoil{20e6, 0.3};

// sigma = lambda tr(eps) I + 2 G eps, written out.
inline Sym3 hooke(const Elastic& el, const Sym3& eps) {
  const double tr = eps[0] + eps[1] + eps[2];
  Sym3 s = 2 * el.G() * eps;
  for (int i = 0; i < 3; ++i) s[i] += el.lambda() * tr;
  return s;
}

struct Eig {
  Eigen::Vector3d val;  // ascending
  Mat3 vec;
};
inline Eig reference_eig(const Sym3& s) {
  Eigen::SelfAdjointEigenSolver<Mat3> es(to_matrix(s));
  return {es.eigenvalues(), es.eigenvectors()};
}

inline Mat3 rotation(double a, double b, double c) {
  return (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}
inline Sym3 from_frame(const Eigen::Vector3d& v, const Mat3& R) {
  return to_voigt(R * v.asDiagonal() * R.transpose());
}

struct McCase {
  double phi, c, psi;
  double t = std::numeric_limits<double>::infinity();
  MohrCoulombParams params() const {
    MohrCoulombParams p;
    p.friction = phi;
    p.cohesion = c;
    p.dilation = psi;
    p.tension_cutoff = t;
    return p;
  }
};

}  // namespace skred::plasticity_test
