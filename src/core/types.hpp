// Basic vector, tensor and stress types shared by every part of skred.
#pragma once
#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <cstdint>

#include "core/inline.hpp"

namespace skred {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
template <int D>
using Mat = Eigen::Matrix<double, D, D>;
using Mat3 = Eigen::Matrix3d;

// Symmetric 3D stress or strain in Voigt order [xx, yy, zz, xy, yz, xz].
// Tensor (not engineering) shear components. Tension positive, as in the seeds.
using Sym3 = Eigen::Matrix<double, 6, 1>;

// A point's stress as stored: plane strain keeps [xx, yy, zz, xy] (its out-of-plane shear
// components are zero), 3D the full Voigt vector. The first four entries have the same order
// and meaning in both, so s[0..3] read alike; full_stress / stored_stress convert.
template <int D>
using PointStress = Eigen::Matrix<double, D == 2 ? 4 : 6, 1>;

template <int D>
SKRED_INLINE Sym3 full_stress(const PointStress<D>& s) {
  if constexpr (D == 2) {
    Sym3 o;
    o << s[0], s[1], s[2], s[3], 0.0, 0.0;
    return o;
  } else {
    return s;
  }
}
template <int D>
SKRED_INLINE PointStress<D> stored_stress(const Sym3& s) {
  if constexpr (D == 2) {
    return s.template head<4>();
  } else {
    return s;
  }
}

inline Mat3 to_matrix(const Sym3& s) {
  Mat3 m;
  m << s[0], s[3], s[5],  //
      s[3], s[1], s[4],   //
      s[5], s[4], s[2];
  return m;
}

inline Sym3 to_voigt(const Mat3& m) {
  Sym3 s;
  s << m(0, 0), m(1, 1), m(2, 2), 0.5 * (m(0, 1) + m(1, 0)), 0.5 * (m(1, 2) + m(2, 1)),
      0.5 * (m(0, 2) + m(2, 0));
  return s;
}

// Double contraction a : b of two symmetric tensors in Voigt storage.
SKRED_INLINE double contract(const Sym3& a, const Sym3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5]);
}

// Embeds a D x D tensor into 3D, filling the out-of-plane part with `fill` on the diagonal
// (plane strain: velocity gradient gets 0, deformation gradient gets 1).
template <int D>
inline Mat3 embed3(const Mat<D>& a, double fill) {
  Mat3 m = Mat3::Identity() * fill;
  m.template topLeftCorner<D, D>() = a;
  return m;
}

// Symmetric part of a D x D tensor embedded in 3D Voigt form (plane strain: zero
// out-of-plane components).
template <int D>
SKRED_INLINE Sym3 sym_voigt(const Mat<D>& a) {
  Sym3 s = Sym3::Zero();
  s[0] = a(0, 0);
  s[1] = a(1, 1);
  s[3] = 0.5 * (a(0, 1) + a(1, 0));
  if constexpr (D == 3) {
    s[2] = a(2, 2);
    s[4] = 0.5 * (a(1, 2) + a(2, 1));
    s[5] = 0.5 * (a(0, 2) + a(2, 0));
  }
  return s;
}

// The D x D block of a symmetric 3D tensor in Voigt form (Sym3 or a stored PointStress).
template <int D, class V>
SKRED_INLINE Mat<D> sym_block(const V& s) {
  if constexpr (D == 2) {
    Mat<2> m;
    m << s[0], s[3], s[3], s[1];
    return m;
  } else {
    return to_matrix(Sym3(s));
  }
}

// Mean stress p = tr(sigma)/3 (tension positive) and von Mises deviatoric stress
// q = sqrt(3 J2). Post eq. 61-62.
inline double mean_stress(const Sym3& s) { return (s[0] + s[1] + s[2]) / 3.0; }
inline double deviatoric_stress(const Sym3& s) {
  const double p = mean_stress(s);
  const double a = s[0] - p, b = s[1] - p, c = s[2] - p;
  const double j2 = 0.5 * (a * a + b * b + c * c) + s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
  return std::sqrt(3.0 * j2);
}

}  // namespace skred
