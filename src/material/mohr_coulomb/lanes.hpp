// Mohr-Coulomb's 3D update for eight points at once, one per lane (core/lanes.hpp), for the
// solver's block update (solver/stress_lanes_3d.hpp): the elastic screens of mohr_coulomb_update,
// the principal decomposition of principal_decomposition_3d and the plane return of step 1 of
// mohr_coulomb_return (Thesis eq. 5.1-5.4), each in the same operations as its scalar form. A lane
// none of them settles (an edge or the apex, a tension cut-off, a hydrostatic trial) is left to
// the scalar update, which decides every case.
#pragma once
#include "core/lanes.hpp"
#include "material/elastic/elastic.hpp"
#include "material/mohr_coulomb/mohr_coulomb.hpp"

namespace skred::lanes {

// The lanes whose trial stress t (Voigt) is admissible by the screens of mohr_coulomb_update:
// clearly_elastic (p and J2), then, for the lanes in `bounded` (not yielding in their last
// update), the Newton bounds on sigma_1 and sigma_3 of principal_bounds with the margin of
// elastic_by_bounds. A lane proven here is elastic on every path of the scalar update.
SKRED_INLINE unsigned mohr_coulomb_elastic(const MohrCoulombConstants& k, const V8 (&t)[6],
                                           unsigned bounded) {
  constexpr double third = 1.0 / 3.0;
  const V8 p = (t[0] + t[1] + t[2]) * third;
  const V8 d0 = t[0] - p, d1 = t[1] - p, d2 = t[2] - p;
  const V8 j2 = 0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + t[3] * t[3] + t[4] * t[4] + t[5] * t[5];
  const V8 room = k.c_cos_phi - p * k.sin_phi, cut = k.tension_cutoff - p;
  const bool cutoff = k.has_tension_cutoff();
  M8 ok = (room > 0.0) & (j2 * (1.0 + k.sin_phi * k.sin_phi * third) < room * room) & (cut > 0.0);
  if (cutoff) ok &= (4.0 * j2 < 3.0 * cut * cut);
  unsigned proven = bits(ok);
  unsigned open = bounded & ~proven & bits(j2 > 0.0);  // (J2 = 0: the scalar update decides)
  if (open == 0u) return proven;
  const V8 j3 =
      d0 * (d1 * d2 - t[4] * t[4]) - t[3] * (t[3] * d2 - t[4] * t[5]) + t[5] * (t[3] * t[4] - d1 * t[5]);
  const V8 r = 2.0 * sqrt8(j2 * third);
  V8 c3 = 4.0 * j3 / (r * r * r);
  c3 = c3 < -1.0 ? splat(-1.0) : c3;
  c3 = c3 > 1.0 ? splat(1.0) : c3;
  V8 u = splat(1.0), w = splat(-1.0);
  const double tol = -1e-10, cut_tol = std::abs(k.tension_cutoff);
  for (int it = 0; it < 8 && open != 0u; ++it) {
    const V8 du = (u * (4.0 * u * u - 3.0) - c3) / (12.0 * u * u - 3.0);
    const V8 dw = (w * (4.0 * w * w - 3.0) - c3) / (12.0 * w * w - 3.0);
    u -= du;
    w -= dw;
    const V8 lo = p + r * w, hi = p + r * u;  // mohr_coulomb_admissible(lo, (lo + hi)/2, hi)
    const V8 scale = k.c_cos_phi + max8(abs8(lo), abs8(hi));
    const V8 f = 0.5 * (hi - lo) + 0.5 * (lo + hi) * k.sin_phi - k.c_cos_phi;
    M8 adm = f <= tol * scale;
    if (cutoff) adm &= (hi - k.tension_cutoff <= tol * (scale + cut_tol));
    const unsigned now = bits(adm) & open;
    proven |= now;
    open &= ~now & ~bits((du < 1e-8) & (dw > -1e-8));
  }
  return proven;
}

// principal_decomposition_3d in lanes: ascending values and their directions (columns).
struct Principal8 {
  V8 values[3];
  V3 vectors[3];
  unsigned valid = 0;  // the lanes with J2 > 0, where the values and directions hold
};
// Valid in the lanes with J2 > 0 (`valid`; the others are the scalar update's).
SKRED_INLINE Principal8 principal_decomposition8(const V8 (&s)[6]) {
  constexpr double third = 1.0 / 3.0;
  const V8 p = (s[0] + s[1] + s[2]) * third;
  const V8 d0 = s[0] - p, d1 = s[1] - p, d2 = s[2] - p, d3 = s[3], d4 = s[4], d5 = s[5];
  const V8 j2 = 0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + d3 * d3 + d4 * d4 + d5 * d5;
  const V8 j3 = d0 * (d1 * d2 - d4 * d4) - d3 * (d3 * d2 - d4 * d5) + d5 * (d3 * d4 - d1 * d5);
  Principal8 out;
  out.valid = bits(j2 > 0.0);
  const V8 r = 2.0 * sqrt8(j2 * third);
  V8 c3 = 4.0 * j3 / (r * r * r);
  c3 = c3 < -1.0 ? splat(-1.0) : c3;
  c3 = c3 > 1.0 ? splat(1.0) : c3;
  const M8 up = c3 >= 0.0;
  const V8 root = detail::largest_cubic_root(abs8(c3));
  const V8 li = r * (up ? root : -root);  // the isolated value of the deviator
  // null_vector: the longest cross product of two rows of d - li I
  const V3 r0{d0 - li, d3, d5}, r1{d3, d1 - li, d4}, r2{d5, d4, d2 - li};
  const V3 c01 = cross(r0, r1), c02 = cross(r0, r2), c12 = cross(r1, r2);
  const V8 n01 = dot(c01, c01), n02 = dot(c02, c02), n12 = dot(c12, c12);
  const M8 m01 = n01 >= n02;
  const V3 c = select(m01, select(n01 >= n12, c01, c12), select(n02 >= n12, c02, c12));
  const V3 v = divided(c, sqrt8(max8(max8(n01, n02), n12)));
  // the plane normal to v and the 2 x 2 block of d in it (eig2)
  const M8 xlead = abs8(v.x) > abs8(v.y);
  V3 e1{xlead ? -v.z : splat(0.0), xlead ? splat(0.0) : v.z, xlead ? v.x : -v.y};
  e1 = divided(e1, sqrt8(dot(e1, e1)));
  const V3 e2 = cross(v, e1);
  auto dm = [&](const V3& a) {
    return V3{d0 * a.x + d3 * a.y + d5 * a.z, d3 * a.x + d1 * a.y + d4 * a.z, d5 * a.x + d4 * a.y + d2 * a.z};
  };
  const V8 a = dot(e1, dm(e1)), d = dot(e2, dm(e2)), b = dot(e1, dm(e2));
  const V8 mm = 0.5 * (a + d), h = 0.5 * (a - d);
  const V8 rr = sqrt8(h * h + b * b);
  const V8 lo = mm - rr, hi = mm + rr;
  const M8 hpos = h >= 0.0;
  const V8 x = hpos ? h + rr : b, y = hpos ? b : rr - h;
  const V8 n = sqrt8(x * x + y * y);
  const M8 round = rr == 0.0;
  const V8 cx = round ? splat(1.0) : x / n, cy = round ? splat(0.0) : y / n;
  const V3 vhi{cx * e1.x + cy * e2.x, cx * e1.y + cy * e2.y, cx * e1.z + cy * e2.z};
  const V3 vlo{cx * e2.x - cy * e1.x, cx * e2.y - cy * e1.y, cx * e2.z - cy * e1.z};
  const V8 vi = dot(v, dm(v));  // the Rayleigh quotient
  out.values[0] = up ? p + lo : p + vi;
  out.values[1] = up ? p + hi : p + lo;
  out.values[2] = up ? p + vi : p + hi;
  out.vectors[0] = select(up, vlo, v);
  out.vectors[1] = select(up, vhi, vlo);
  out.vectors[2] = select(up, v, vhi);
  auto order = [&](int i) {  // keep the ascending order round-off may swap
    const M8 swap = out.values[i + 1] < out.values[i];
    const V8 lo_v = swap ? out.values[i + 1] : out.values[i], hi_v = swap ? out.values[i] : out.values[i + 1];
    const V3 lo_d = select(swap, out.vectors[i + 1], out.vectors[i]);
    const V3 hi_d = select(swap, out.vectors[i], out.vectors[i + 1]);
    out.values[i] = lo_v;
    out.values[i + 1] = hi_v;
    out.vectors[i] = lo_d;
    out.vectors[i + 1] = hi_d;
  };
  order(0);
  order(1);
  order(0);
  return out;
}

// sum_i values[i] v_i v_i^T in Voigt storage (from_principal).
SKRED_INLINE void from_principal8(const V8 (&values)[3], const V3 (&v)[3], V8 (&s)[6]) {
  const V8 x[3] = {v[0].x, v[1].x, v[2].x}, y[3] = {v[0].y, v[1].y, v[2].y}, z[3] = {v[0].z, v[1].z, v[2].z};
  from_principal(values, x, y, z, s);
}

// Step 1 of mohr_coulomb_return without a tension cut-off, on the ascending principal trial
// values st: the lanes admissible within kYieldRelTol after all (`elastic`), and those whose plane
// return sigma = st - dl D b (eq. 5.3-5.4) stays ordered (`plane`), with sigma and d_eps_p.
struct PlaneReturn8 {
  unsigned elastic = 0, plane = 0;
  V8 sigma[3], deps_p[3];
};
SKRED_INLINE PlaneReturn8 plane_return8(const ElasticConstants& e, const MohrCoulombConstants& k, V8 sin_psi,
                                        const V8 (&st)[3]) {
  PlaneReturn8 out;
  const V8 scale = k.c_cos_phi + max8(abs8(st[0]), abs8(st[2]));
  const V8 f = 0.5 * (st[2] - st[0]) + 0.5 * (st[0] + st[2]) * k.sin_phi - k.c_cos_phi;
  out.elastic = bits(f <= kYieldRelTol * scale);
  const double sp = k.sin_phi;
  const double a0 = -(1.0 - sp) * 0.5, a2 = (1.0 + sp) * 0.5;
  const V8 b0 = -(1.0 - sin_psi) * 0.5, b2 = (1.0 + sin_psi) * 0.5;
  // (a_1 = b_1 = 0) D b = lambda (sum b) 1 + 2G b (stiffness_times)
  const V8 db1 = e.lambda * (b0 + b2), db0 = db1 + e.two_g * b0, db2 = db1 + e.two_g * b2;
  const V8 dl = (a0 * st[0] + a2 * st[2] - k.c_cos_phi) / (a0 * db0 + a2 * db2);
  out.sigma[0] = st[0] - dl * db0;
  out.sigma[1] = st[1] - dl * db1;
  out.sigma[2] = st[2] - dl * db2;
  out.plane = bits((out.sigma[1] <= out.sigma[2]) & (out.sigma[0] <= out.sigma[1])) & ~out.elastic;
  out.deps_p[0] = dl * b0;
  out.deps_p[1] = lanes::splat(0.0);
  out.deps_p[2] = dl * b2;
  return out;
}

}  // namespace skred::lanes
