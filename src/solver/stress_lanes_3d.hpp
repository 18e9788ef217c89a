// The 3D stress update of a block of eight points in the lanes of vectors (docs/method.md, "The 3D
// stress update in lanes"). A point's scalar update is a long dependent chain (trial stress, the
// Mohr-Coulomb screens with their square root and divisions, the push-forward's division, F, Fe,
// the work), and the out-of-order core overlaps little of one point's chain with the next's. Here
// the eight chains run side by side, one per lane: the same equations as stress_update.hpp and
// kinematics_3d.hpp (Thesis eq. 2.5, 2.20, 3.2, 4.4, 4.16; Post eq. 72-73), with Mohr-Coulomb's
// screens and plane return from material/mohr_coulomb/lanes.hpp. A lane they do not settle (an
// edge or apex return, a tension cut-off's plastic step, another model, a second material, a
// point the selection leaves out) is left to the scalar update.
#pragma once
#include <cstring>

#include "core/inline.hpp"
#include "core/lanes.hpp"
#include "material/material.hpp"
#include "material/mohr_coulomb/lanes.hpp"
#include "solver/kinematics_3d.hpp"
#include "solver/stress_arrays.hpp"

namespace skred::lanes3d {

using lanes::kLanes;
using lanes::load;
using lanes::load_mat;
using lanes::M8;
using lanes::store_mat;
using lanes::V8;
static_assert(kPointBlock == kLanes, "one point per lane");
static_assert(sizeof(Mat3) == 9 * sizeof(double) && sizeof(PointStress<3>) == 6 * sizeof(double),
              "the point arrays are records of 9 and 6 contiguous doubles");

// Component c of eight consecutive records of `Stride` doubles from the lanes set in `mask`
// (lanes::load's way back).
template <int Stride>
SKRED_INLINE void store(double* __restrict base, int c, V8 v, unsigned mask) {
  if (mask == 0xffu) {
    for (int l = 0; l < kLanes; ++l) base[l * Stride + c] = v[l];
  } else {
    for (int l = 0; l < kLanes; ++l)
      if ((mask >> l) & 1u) base[l * Stride + c] = v[l];
  }
}

// The update of the block's points p0 .. p0 + 7 in lanes, with their velocity gradients in m[]
// (update_point_stress): d_eps = sym(g), g = dt grad v (eq. 2.20); S = sigma^k + C : d_eps
// (eq. 2.5) and, for Mohr-Coulomb, its return (eq. 5.2-5.4); sigma = dF S dF^T / det dF
// (eq. 4.4); F <- dF F (eq. 3.2), Fe <- (I + d_eps - d_eps_p) Fe (Post eq. 72-73), V = det F V0
// and the trapezoidal work (eq. 4.16) split into stored and dissipated. Then m[] holds -V sigma
// for the force scatter. Returns the lanes it updated; work, dissipation and `bad` as
// update_booked; the other lanes are the scalar update's.
template <class Sel>
SKRED_INLINE unsigned update_block(const StressArrays<3>& S, long p0, const Sel& sel, Mat3 (&m)[kLanes],
                                   double dt, double& work, double& dissipation, long& bad) {
  using lanes::bits;
  using lanes::splat;
  unsigned done = 0;
  for (int l = 0; l < kLanes; ++l) done |= (sel(p0 + l) ? 1u : 0u) << l;
  if (done == 0u) return 0u;
  const int id = S.single ? 0 : S.material[p0];
  if (!S.single)
    for (int l = 1; l < kLanes; ++l)
      if (S.material[p0 + l] != id) return 0u;
  const Material& mat = S.mats[id];
  const bool mohr_coulomb = mat.model == Model::MohrCoulomb || mat.model == Model::Tresca;
  if (mat.hyperelastic || !(mohr_coulomb || mat.model == Model::LinearElastic)) return 0u;

  // d_eps and the trial stress
  V8 gm[9];  // grad v, column-major
  load_mat(m[0].data(), gm);
  V8 g[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) g[i][j] = dt * gm[i + 3 * j];
  const V8 e[6] = {g[0][0],
                   g[1][1],
                   g[2][2],
                   0.5 * (g[0][1] + g[1][0]),
                   0.5 * (g[1][2] + g[2][1]),
                   0.5 * (g[0][2] + g[2][0])};
  double* const sd = S.stress[p0].data();
  V8 old[6], t[6];
  const double two_g = mat.elastic_constants.two_g;
  const V8 tr = e[0] + e[1] + e[2], lt = mat.elastic_constants.lambda * tr;
  for (int c = 0; c < 6; ++c) {
    old[c] = load<6>(sd, c);
    t[c] = old[c] + (c < 3 ? two_g * e[c] + lt : two_g * e[c]);
  }

  // the return: S = t where elastic; on the yield plane where plastic (eq. 5.3-5.4)
  V8 sv[6], ep[6];  // S and d_eps_p
  for (int c = 0; c < 6; ++c) {
    sv[c] = t[c];
    ep[c] = splat(0.0);
  }
  unsigned plastic = 0;
  V8 ep_shear = splat(0.0), ep_volume = splat(0.0), vstrain = splat(0.0);
  if (mohr_coulomb) {
    const MohrCoulombConstants& k = mat.mohr_coulomb_constants;
    unsigned bounded = 0;
    for (int l = 0; l < kLanes; ++l) {
      bounded |= (S.state[p0 + l].yielding ? 0u : 1u) << l;
      vstrain[l] = S.state[p0 + l].volume_strain;
    }
    vstrain += tr;
    const unsigned elastic = lanes::mohr_coulomb_elastic(k, t, bounded) & done;
    unsigned open = done & ~elastic;
    if (open != 0u && !k.has_tension_cutoff()) {
      const lanes::Principal8 pd = lanes::principal_decomposition8(t);
      const V8 sin_psi = vstrain >= k.max_volume_strain ? splat(0.0) : splat(k.sin_psi);
      const lanes::PlaneReturn8 r = lanes::plane_return8(mat.elastic_constants, k, sin_psi, pd.values);
      plastic = open & r.plane & pd.valid;
      open &= ~((r.elastic & pd.valid) | plastic);  // (elastic after all: S = t, as above)
      V8 rs[6], re[6];
      lanes::from_principal8(r.sigma, pd.vectors, rs);
      lanes::from_principal8(r.deps_p, pd.vectors, re);
      const lanes::M8 pm = lanes::lanes_of(plastic);
      for (int c = 0; c < 6; ++c) {
        sv[c] = pm ? rs[c] : sv[c];
        ep[c] = pm ? re[c] : ep[c];
      }
      // record_plastic_strain: 2 sqrt(J2(d_eps_p)) and tr(d_eps_p)
      const V8 a = r.deps_p[0] - r.deps_p[1], b = r.deps_p[1] - r.deps_p[2], c = r.deps_p[2] - r.deps_p[0];
      ep_shear = 2.0 * lanes::sqrt8((a * a + b * b + c * c) / 6.0);
      ep_volume = r.deps_p[0] + r.deps_p[1] + r.deps_p[2];
    }
    done &= ~open;
    if (done == 0u) return 0u;
  }

  // sigma = dF S dF^T / det dF (eq. 4.4), dF = I + g
  V8 s[6];
  for (int k = 0; k < 6; ++k) s[k] = sv[k];
  kinematics3::push_forward(g, s);

  // F <- dF F, Fe <- (I + d_eps - d_eps_p) Fe, V = det F V0
  double* const fd = S.F[p0].data();
  V8 fv[9];
  load_mat(fd, fv);
  V8 f[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) f[i][j] = fv[i + 3 * j];
  const M8 keep = lanes::lanes_of(done);
  V8 fn[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      fn[i][j] = f[i][j] + g[i][0] * f[0][j] + g[i][1] * f[1][j] + g[i][2] * f[2][j];
      fv[i + 3 * j] = keep ? fn[i][j] : f[i][j];
    }
  store_mat(fd, fv);
  V8 ee[6];  // the elastic strain increment d_eps - d_eps_p
  for (int k = 0; k < 6; ++k) ee[k] = plastic ? e[k] - ep[k] : e[k];
  if (S.Fe) {  // tracked only for the frames that hold Fe, Fp or stress_from_Fe
    double* const hd = S.Fe[p0].data();
    V8 hv[9];
    load_mat(hd, hv);
    V8 h[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) h[i][j] = hv[i + 3 * j];
    const V8 em[3][3] = {{ee[0], ee[3], ee[5]}, {ee[3], ee[1], ee[4]}, {ee[5], ee[4], ee[2]}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const V8 hn = h[i][j] + em[i][0] * h[0][j] + em[i][1] * h[1][j] + em[i][2] * h[2][j];
        hv[i + 3 * j] = keep ? hn : h[i][j];
      }
    store_mat(hd, hv);
  }
  const V8 detf = fn[0][0] * (fn[1][1] * fn[2][2] - fn[1][2] * fn[2][1]) -
                  fn[0][1] * (fn[1][0] * fn[2][2] - fn[1][2] * fn[2][0]) +
                  fn[0][2] * (fn[1][0] * fn[2][1] - fn[1][1] * fn[2][0]);
  V8 v0;
  std::memcpy(&v0, S.volume0 + p0, sizeof(V8));
  const V8 volume = v0 * detf;
  if (S.det_f) store<1>(S.det_f + p0, 0, detf, done);

  // the work (eq. 4.16), the stress, the check of the point, and -V sigma for the scatter
  V8 mid[6];
  for (int k = 0; k < 6; ++k) mid[k] = old[k] + s[k];
  auto contract = [&](const V8(&x)[6]) {
    return mid[0] * x[0] + mid[1] * x[1] + mid[2] * x[2] +
           2.0 * (mid[3] * x[3] + mid[4] * x[4] + mid[5] * x[5]);
  };
  const V8 half_v = 0.5 * volume;
  const V8 stored = half_v * contract(ee), dissipated = half_v * contract(ep);
  const V8 sum = s[0] + s[1] + s[2] + s[3] + s[4] + s[5];
  const M8 sound = (volume > 0.0) & (sum - sum == 0.0);  // det F > 0 and a finite stress
  for (int k = 0; k < 6; ++k) store<6>(sd, k, s[k], done);
  const V8 nv = -volume;
  const V8 fm[9] = {nv * s[0], nv * s[3], nv * s[5], nv * s[3], nv * s[1],
                    nv * s[4], nv * s[5], nv * s[4], nv * s[2]};
  for (int k = 0; k < 9; ++k) gm[k] = keep ? fm[k] : gm[k];
  store_mat(m[0].data(), gm);
  const unsigned unsound = done & ~bits(sound);
  for (int l = 0; l < kLanes; ++l) {
    if (!((done >> l) & 1u)) continue;
    work += stored[l];
    if (mohr_coulomb) {
      PointState& st = S.state[p0 + l];
      st.volume_strain = vstrain[l];
      st.yielding = (plastic >> l) & 1u;
      if ((plastic >> l) & 1u) {
        dissipation += dissipated[l];
        st.plastic_shear_strain += ep_shear[l];
        st.plastic_volume_strain += ep_volume[l];
      }
    }
    if ((unsound >> l) & 1u) bad = std::min(bad, p0 + l);
  }
  return done;
}

}  // namespace skred::lanes3d
