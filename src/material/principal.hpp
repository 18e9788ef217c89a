// Principal decomposition of a symmetric 3D tensor in Voigt storage, in the seeds' order:
// sigma_1 <= sigma_2 <= sigma_3, tension positive (Thesis eq. 5.1). The plastic return
// mappings (Clausen et al. 2006) work on the principal values and rotate the result back with
// the principal directions of the trial stress.
//
// Plane strain (s[4] == s[5] == 0, the hot case) uses a closed-form 2 x 2 in-plane solution plus
// the out-of-plane value s[2] with direction e_z; the general 3D case a closed form on the
// deviator's cubic (principal_decomposition_3d), accurate to round-off also for near-equal
// eigenvalues, where Eigen's closed-form computeDirect loses accuracy (rebuild error up to
// 4e-8 |s|), and several times faster than Eigen's tridiagonal QR. The 3D elastic screen needs
// only bounds on the extreme values (principal_bounds).
// Fixed-size Eigen types only: no heap allocation, no exceptions.
#pragma once
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <utility>
#include "core/inline.hpp"

#include "core/types.hpp"

namespace skred {

using Vec3 = Eigen::Vector3d;

struct Principal {
  Vec3 values;   // ascending: values[0] = sigma_1 <= values[1] = sigma_2 <= values[2] = sigma_3
  Mat3 vectors;  // orthonormal columns, column i is the direction of values[i]
};

namespace detail {

// In-plane 2 x 2 block [[a, b], [b, d]]: eigenvalues lo <= hi and the unit direction (cx, cy) of
// hi (the direction of lo is (-cy, cx)). The eigenvector formula is chosen per sign of a - d so
// that it involves no cancellation.
SKRED_INLINE void eig2(double a, double d, double b, double& lo, double& hi, double& cx, double& cy) {
  const double m = 0.5 * (a + d), h = 0.5 * (a - d);
  const double r = std::sqrt(h * h + b * b);  // stresses in Pa: no overflow concern
  lo = m - r;
  hi = m + r;
  if (r == 0.0) {
    cx = 1.0;
    cy = 0.0;
    return;
  }
  // (A - hi I) v = 0: v = (h + r, b) if h >= 0, v = (b, r - h) if h < 0.
  double x, y;
  if (h >= 0.0) {
    x = h + r;
    y = b;
  } else {
    x = b;
    y = r - h;
  }
  const double n = std::sqrt(x * x + y * y);
  cx = x / n;
  cy = y / n;
}

// Sorts three (value, slot) pairs ascending with three compare-swaps.
SKRED_INLINE void sort3(double (&v)[3], int (&k)[3]) {
  if (v[1] < v[0]) {
    std::swap(v[0], v[1]);
    std::swap(k[0], k[1]);
  }
  if (v[2] < v[1]) {
    std::swap(v[1], v[2]);
    std::swap(k[1], k[2]);
  }
  if (v[1] < v[0]) {
    std::swap(v[0], v[1]);
    std::swap(k[0], k[1]);
  }
}

}  // namespace detail

SKRED_INLINE bool is_plane(const Sym3& s) { return s[4] == 0.0 && s[5] == 0.0; }

// Plane strain decomposition for the return mappings: the ascending values of {in-plane minor,
// in-plane major, sigma_zz}, the slot each came from (0, 1, 2 in that order), and the major
// in-plane direction theta as cos 2 theta = h / r, sin 2 theta = b / r (one square root, no
// normalised vectors: the rotation back needs only cos^2, sin^2 and cos sin of theta).
struct PlanePrincipal {
  double v[3];
  int slot[3];
  double h, b, r;  // (s_xx - s_yy)/2, s_xy, radius of Mohr's circle of the in-plane block

  // Sum over the three slots of values[i] times the dyad of slot i's direction, as a Voigt
  // vector V: Sym3, or the four plane-strain components [xx, yy, zz, xy].
  template <class V>
  SKRED_INLINE V rebuild(const double (&by_slot)[3]) const {
    const double c2 = r > 0.0 ? h / r : 1.0, s2 = r > 0.0 ? b / r : 0.0;
    const double xx = 0.5 * (1.0 + c2), yy = 0.5 * (1.0 - c2), xy = 0.5 * s2;
    const double lo = by_slot[0], hi = by_slot[1];
    V out = V::Zero();
    out[0] = lo * yy + hi * xx;
    out[1] = lo * xx + hi * yy;
    out[2] = by_slot[2];
    out[3] = (hi - lo) * xy;
    return out;
  }
};

template <class V>
SKRED_INLINE PlanePrincipal plane_principal(const V& s) {
  PlanePrincipal p;
  const double m = 0.5 * (s[0] + s[1]);
  p.h = 0.5 * (s[0] - s[1]);
  p.b = s[3];
  p.r = std::sqrt(p.h * p.h + p.b * p.b);
  p.v[0] = m - p.r;
  p.v[1] = m + p.r;
  p.v[2] = s[2];
  p.slot[0] = 0;
  p.slot[1] = 1;
  p.slot[2] = 2;
  detail::sort3(p.v, p.slot);
  return p;
}

// Bounds lo <= sigma_1 and hi >= sigma_3 on the extreme principal values, without
// trigonometry, for the 3D elastic screen. With p = tr(s)/3 and r = 2 sqrt(J2/3) the principal
// values are p + r u, u the roots of 4u^3 - 3u = cos(3 theta) = 4 J3 / r^3. Newton's method
// started at u = 1 (u = -1) approaches the largest (smallest) root monotonically from outside,
// because the cubic is convex beyond its largest root and concave below its smallest, so every
// iterate is a bound. It stops when both steps are below 1e-8 (quadratic convergence: the
// bounds are then within ~1e-15 r) or after eight steps, which leave a near-double root up to
// a few tenths of a per cent of r outside (the caller then takes the accurate path). Since
// every iterate is a bound, `enough(bounds)` may stop the iteration early (the elastic screen
// stops as soon as the bounds prove the stress admissible).
struct PrincipalBounds {
  double lo, hi;
};
template <class Enough>
SKRED_INLINE PrincipalBounds principal_bounds(const Sym3& s, Enough&& enough) {
  // (bounds: p and r by a product with 1/3, not a division, which the chain would wait for)
  constexpr double third = 1.0 / 3.0;
  const double p = (s[0] + s[1] + s[2]) * third;
  const double d0 = s[0] - p, d1 = s[1] - p, d2 = s[2] - p;
  const double j2 = 0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
  if (!(j2 > 0.0)) return {p, p};
  const double j3 =
      d0 * (d1 * d2 - s[4] * s[4]) - s[3] * (s[3] * d2 - s[4] * s[5]) + s[5] * (s[3] * s[4] - d1 * s[5]);
  const double r = 2.0 * std::sqrt(j2 * third);
  const double c3 = std::clamp(4.0 * j3 / (r * r * r), -1.0, 1.0);
  double u = 1.0, w = -1.0;
  for (int k = 0; k < 8; ++k) {
    const double du = (u * (4.0 * u * u - 3.0) - c3) / (12.0 * u * u - 3.0);
    const double dw = (w * (4.0 * w * w - 3.0) - c3) / (12.0 * w * w - 3.0);
    u -= du;
    w -= dw;
    if (enough(PrincipalBounds{p + r * w, p + r * u})) break;
    if (du < 1e-8 && dw > -1e-8) break;  // both converged: the next error is ~ the step squared
  }
  return {p + r * w, p + r * u};
}
SKRED_INLINE PrincipalBounds principal_bounds(const Sym3& s) {
  return principal_bounds(s, [](const PrincipalBounds&) { return false; });
}

namespace detail {

// The largest root u of 4u^3 - 3u = c for c in [0, 1] (u = cos(acos(c)/3) in [cos 30 deg, 1]).
// The root is simple (the cubic's slope there is at least 6) and analytic in c, so a degree-5
// polynomial (a least-squares Chebyshev fit, within 1.3e-6 of the root) and one Halley step,
// which cubes the error, give it to round-off (3e-16 against cos(acos(c)/3) on 2e5 samples):
// one division instead of Newton's four or acos and cos.
// (T: double, or eight lanes of them, core/lanes.hpp.)
template <class T>
SKRED_INLINE T largest_cubic_root(T c) {
  T u = T{} + 0.0019631785446316274;
  u = u * c - 0.008972271811933727;
  u = u * c + 0.021865698860087997;
  u = u * c - 0.0474918764903172;
  u = u * c + 0.1666095405450996;
  u = u * c + 0.8660266884397412;
  const T f = u * (4.0 * u * u - 3.0) - c, f1 = 12.0 * u * u - 3.0, f2 = 24.0 * u;
  return u - f * f1 / (f1 * f1 - 0.5 * f * f2);
}

// A unit vector in the null space of the rank-2 matrix [[a0, a3, a5], [a3, a1, a4], [a5, a4, a2]]:
// the longest of the three cross products of its rows.
SKRED_INLINE Vec3 null_vector(double a0, double a1, double a2, double a3, double a4, double a5) {
  const Vec3 r0(a0, a3, a5), r1(a3, a1, a4), r2(a5, a4, a2);
  const Vec3 c01 = r0.cross(r1), c02 = r0.cross(r2), c12 = r1.cross(r2);
  const double n01 = c01.squaredNorm(), n02 = c02.squaredNorm(), n12 = c12.squaredNorm();
  const Vec3& c = n01 >= n02 ? (n01 >= n12 ? c01 : c12) : (n02 >= n12 ? c02 : c12);
  return c / std::sqrt(std::max({n01, n02, n12}));
}

// The general 3D decomposition in closed form, without iteration over the matrix: on the
// deviator d = s - p I (p = tr s / 3) with r = 2 sqrt(J2/3), the principal values are p + r u,
// u the roots of 4u^3 - 3u = cos(3 theta) = 4 J3 / r^3 (the screen's cubic above). The root
// farthest from the other two (the largest for J3 >= 0, else the smallest) is simple, at
// least 0.87 r from them, so largest_cubic_root finds it and a null vector of d - r u I its
// direction, both to round-off. The other two come from the 2 x 2 block of d in the plane
// normal to it (eig2), which is accurate also when they are equal or nearly so, where the
// trigonometric formula of Eigen's computeDirect loses half the digits.
inline Principal principal_decomposition_3d(const Sym3& s) {
  Principal out;
  constexpr double third = 1.0 / 3.0;  // (products, not divisions, on the chain to the roots)
  const double p = (s[0] + s[1] + s[2]) * third;
  const double d0 = s[0] - p, d1 = s[1] - p, d2 = s[2] - p, d3 = s[3], d4 = s[4], d5 = s[5];
  const double j2 = 0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + d3 * d3 + d4 * d4 + d5 * d5;
  if (!(j2 > 0.0)) {  // hydrostatic: every direction is principal
    out.values = Vec3::Constant(p);
    out.vectors = Mat3::Identity();
    return out;
  }
  const double j3 = d0 * (d1 * d2 - d4 * d4) - d3 * (d3 * d2 - d4 * d5) + d5 * (d3 * d4 - d1 * d5);
  const double r = 2.0 * std::sqrt(j2 * third);
  const double c3 = std::clamp(4.0 * j3 / (r * r * r), -1.0, 1.0);
  const double ui = c3 >= 0.0 ? largest_cubic_root(c3) : -largest_cubic_root(-c3);
  const double li = r * ui;  // the isolated value of the deviator
  const Vec3 v = null_vector(d0 - li, d1 - li, d2 - li, d3, d4, d5);
  // An orthonormal basis (e1, e2) of the plane normal to v; e1 from v_z and the larger of v_x
  // and v_y, so its length before normalising is at least 1/sqrt(2) of v's.
  Vec3 e1 = std::abs(v[0]) > std::abs(v[1]) ? Vec3(-v[2], 0.0, v[0]) : Vec3(0.0, v[2], -v[1]);
  e1.normalize();
  const Vec3 e2 = v.cross(e1);
  const Mat3 dm = (Mat3() << d0, d3, d5, d3, d1, d4, d5, d4, d2).finished();
  const Vec3 de1 = dm * e1, de2 = dm * e2;
  double lo, hi, cx, cy;
  eig2(e1.dot(de1), e2.dot(de2), e1.dot(de2), lo, hi, cx, cy);
  const Vec3 vhi = cx * e1 + cy * e2, vlo = cx * e2 - cy * e1;
  const double vi = v.dot(dm * v);  // the Rayleigh quotient: li to round-off
  if (c3 >= 0.0) {
    out.values = Vec3(p + lo, p + hi, p + vi);
    out.vectors << vlo, vhi, v;
  } else {
    out.values = Vec3(p + vi, p + lo, p + hi);
    out.vectors << v, vlo, vhi;
  }
  // Round-off can only swap values within a near-equal pair; keep the ascending order.
  for (int i = 0; i < 2; ++i)
    if (out.values[i + 1] < out.values[i]) {
      std::swap(out.values[i], out.values[i + 1]);
      out.vectors.col(i).swap(out.vectors.col(i + 1));
    }
  if (out.values[1] < out.values[0]) {
    std::swap(out.values[0], out.values[1]);
    out.vectors.col(0).swap(out.vectors.col(1));
  }
  return out;
}

}  // namespace detail

// Principal values (ascending) and orthonormal directions.
inline Principal principal_decomposition(const Sym3& s) {
  Principal p;
  if (is_plane(s)) {
    double lo, hi, cx, cy;
    detail::eig2(s[0], s[1], s[3], lo, hi, cx, cy);
    // Candidate columns: 0 -> lo (-cy, cx, 0), 1 -> hi (cx, cy, 0), 2 -> zz (0, 0, 1).
    Mat3 cand;
    cand << -cy, cx, 0.0,  //
        cx, cy, 0.0,       //
        0.0, 0.0, 1.0;
    double v[3] = {lo, hi, s[2]};
    int k[3] = {0, 1, 2};
    detail::sort3(v, k);
    p.values = Vec3(v[0], v[1], v[2]);
    for (int i = 0; i < 3; ++i) p.vectors.col(i) = cand.col(k[i]);
    return p;
  }
  return detail::principal_decomposition_3d(s);
}

// Principal values only, ascending.
inline Vec3 principal_values(const Sym3& s) { return principal_decomposition(s).values; }

// Inverse: sum_i l[i] v_i v_i^T in Voigt storage (tensor shear components), with v_i = (x[i],
// y[i], z[i]). T is a double, or a vector of eight points' values side by side
// (mohr_coulomb/lanes.hpp). Exact zeros are preserved for plane-strain directions (v_z = 0
// in-plane, e_z out of plane).
template <class T>
SKRED_INLINE void from_principal(const T (&l)[3], const T (&x)[3], const T (&y)[3], const T (&z)[3],
                                 T (&s)[6]) {
  for (int k = 0; k < 6; ++k) s[k] = T{};
  for (int i = 0; i < 3; ++i) {
    s[0] += l[i] * x[i] * x[i];
    s[1] += l[i] * y[i] * y[i];
    s[2] += l[i] * z[i] * z[i];
    s[3] += l[i] * x[i] * y[i];
    s[4] += l[i] * y[i] * z[i];
    s[5] += l[i] * x[i] * z[i];
  }
}
SKRED_INLINE Sym3 from_principal(const Vec3& values, const Mat3& V) {
  const double l[3] = {values[0], values[1], values[2]};
  const double x[3] = {V(0, 0), V(0, 1), V(0, 2)}, y[3] = {V(1, 0), V(1, 1), V(1, 2)},
               z[3] = {V(2, 0), V(2, 1), V(2, 2)};
  double s[6];
  from_principal(l, x, y, z, s);
  Sym3 out;
  out << s[0], s[1], s[2], s[3], s[4], s[5];
  return out;
}

}  // namespace skred
