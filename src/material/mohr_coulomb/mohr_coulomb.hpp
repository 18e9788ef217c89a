// Non-associated Mohr-Coulomb plasticity (Thesis eq. 5.1-5.4, Paper III eq. C.37-C.40) with
// an optional Rankine tension cut-off and the dilation cut-off of Paper III §C.3.2. Tresca is
// friction = dilation = 0.
//
// Stress return in principal stress space after Clausen, Damkilde & Andersen (2006, 2007):
// the trial stress sigma^tr = sigma^k + C : d_eps (eq. 5.2) is decomposed into ordered
// principal values sigma_1 <= sigma_2 <= sigma_3 (tension positive) and directions; the
// principal values are returned with d_sigma = -sum_i dl_i D b_i (eq. 5.3, b_i = dg_i/dsigma
// of the active planes, D the principal-space elastic stiffness) to the yield plane, one of the
// two edges, the apex or (with the cut-off) the Rankine plane and its intersections; then the
// result is rotated back with the trial's principal directions. All returns are closed form
// (at most a 3 x 3 linear solve), no iteration. See mohr_coulomb.cpp for the region logic.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/inline.hpp"
#include "material/elastic/elastic.hpp"
#include "material/mohr_coulomb/params.hpp"
#include "material/principal.hpp"
#include "material/state.hpp"

namespace skred {

// Derived constants of a MohrCoulombParams block (computed once per material; the update
// function taking MohrCoulombParams builds them on every call).
struct MohrCoulombConstants {
  double sin_phi = 0.0, cos_phi = 1.0;
  double c_cos_phi = 0.0;  // c cos(phi), the constant of eq. 5.1
  double sin_psi = 0.0;    // sin(psi) of eq. 5.4
  // Apex stress c cot(phi) (+inf for phi = 0: Tresca has no apex).
  double apex = std::numeric_limits<double>::infinity();
  // Effective tension cut-off: +inf when absent or when it lies at or above the apex.
  double tension_cutoff = std::numeric_limits<double>::infinity();
  // Volume strain at which the void ratio (1 + e0) exp(eps_v) - 1 reaches e_max, i.e.
  // ln((1 + e_max)/(1 + e0)); +inf when the dilation cut-off is disabled (e_max <= 0).
  double max_volume_strain = std::numeric_limits<double>::infinity();

  MohrCoulombConstants() = default;
  explicit MohrCoulombConstants(const MohrCoulombParams& p)
      : sin_phi(std::sin(p.friction)),
        cos_phi(std::cos(p.friction)),
        c_cos_phi(p.cohesion * std::cos(p.friction)),
        sin_psi(std::sin(p.dilation)) {
    if (sin_phi > 0.0) apex = c_cos_phi / sin_phi;
    // A cut-off at (or within round-off of) the apex or above it has no effect.
    if (!(sin_phi > 0.0) || p.tension_cutoff < apex - 1e-12 * std::abs(apex))
      tension_cutoff = p.tension_cutoff;
    if (p.max_void_ratio > 0.0)
      max_volume_strain = std::log((1.0 + p.max_void_ratio) / (1.0 + p.initial_void_ratio));
  }
  bool has_tension_cutoff() const { return tension_cutoff < std::numeric_limits<double>::infinity(); }
};

// Which part of the yield surface the return went to. "Compression edge" is sigma_2 = sigma_3
// (triaxial compression), "extension edge" sigma_1 = sigma_2 (triaxial extension).
enum class MohrCoulombRegion : std::uint8_t {
  Elastic,
  Plane,              // f = 0
  CompressionEdge,    // f = 0, sigma_2 = sigma_3
  ExtensionEdge,      // f = 0, sigma_1 = sigma_2
  Apex,               // sigma_1 = sigma_2 = sigma_3 = c cot(phi)
  Tension,            // sigma_3 = t (Rankine plane)
  TensionEdge,        // sigma_2 = sigma_3 = t
  TensionApex,        // sigma_1 = sigma_2 = sigma_3 = t
  PlaneTension,       // f = 0, sigma_3 = t
  ExtensionCorner,    // f = 0, sigma_1 = sigma_2, sigma_3 = t
  CompressionCorner,  // f = 0, sigma_2 = sigma_3 = t
};

// Yield function eq. 5.1 of ascending principal stresses (tension positive).
SKRED_INLINE double mohr_coulomb_yield(const MohrCoulombConstants& k, const Vec3& p) {
  return 0.5 * (p[2] - p[0]) + 0.5 * (p[0] + p[2]) * k.sin_phi - k.c_cos_phi;
}
inline double mohr_coulomb_yield(const MohrCoulombParams& mc, const Vec3& principal_ascending) {
  return mohr_coulomb_yield(MohrCoulombConstants(mc), principal_ascending);
}

// Relative tolerance of the elastic check: the trial is elastic when
//   f <= 1e-12 (c cos(phi) + max(|sigma_1|, |sigma_3|))   and   sigma_3 - t <= 1e-12 (|t| + same),
// i.e. within round-off of the stress magnitude (applied by mohr_coulomb_return; the inline
// screening in mohr_coulomb_update applies it directly in plane strain).
inline constexpr double kYieldRelTol = 1e-12;

// The return in principal space. `sigma`: in = ascending trial principal values, out = returned
// values (still ascending); `deps_p`: out = principal plastic strain increment. `sin_psi` is the
// dilation in use (0 after the dilation cut-off). Assumes the trial is not admissible.
MohrCoulombRegion mohr_coulomb_return(const ElasticConstants& e, const MohrCoulombConstants& k,
                                      double sin_psi, Vec3& sigma, Vec3& deps_p);

namespace detail {
// Plastic paths of mohr_coulomb_update (out of line: the elastic path stays small).
Sym3 mohr_coulomb_plastic(const ElasticConstants& e, const MohrCoulombConstants& k, Sym3& stress,
                          const Sym3& trial, PointState& state, MohrCoulombRegion* region);
// Plastic bookkeeping of the state: engineering shear 2 sqrt(J2) and volume of d_eps_p.
SKRED_INLINE void record_plastic_strain(const Vec3& ep, PointState& state) {
  const double j2 = ((ep[0] - ep[1]) * (ep[0] - ep[1]) + (ep[1] - ep[2]) * (ep[1] - ep[2]) +
                     (ep[2] - ep[0]) * (ep[2] - ep[0])) /
                    6.0;
  state.plastic_shear_strain += 2.0 * std::sqrt(j2);
  state.plastic_volume_strain += ep.sum();
  state.yielding = 1;
}

// Plane strain (the hot case): the plane return of step 1 inline (without the cut-off), the
// rest through mohr_coulomb_return; the rotation back uses the in-plane angle of the trial.
// V: Sym3, or the four stored plane-strain components.
template <class V>
SKRED_INLINE V mohr_coulomb_plastic_plane(const ElasticConstants& e, const MohrCoulombConstants& k, V& stress,
                                          const V& trial, const PlanePrincipal& pp, PointState& state,
                                          MohrCoulombRegion* region) {
  // Dilation cut-off (Paper III §C.3.2): psi = 0 once e = (1 + e0) exp(eps_v) - 1 >= e_max,
  // evaluated with the updated volume strain.
  const double sq = state.volume_strain >= k.max_volume_strain ? 0.0 : k.sin_psi;
  Vec3 s(pp.v[0], pp.v[1], pp.v[2]), ep;
  MohrCoulombRegion r = MohrCoulombRegion::Plane;
  bool done = false;
  if (!k.has_tension_cutoff()) {
    // Step 1, the plane return sigma = sigma^tr - dl D b (eq. 5.3-5.4) with the a and b of the
    // yield plane (see mohr_coulomb.cpp).
    const double sp = k.sin_phi;
    const double a0 = -0.5 * (1.0 - sp), a2 = 0.5 * (1.0 + sp);
    const double b0 = -0.5 * (1.0 - sq), b2 = 0.5 * (1.0 + sq);
    const double lb = e.lambda * (b0 + b2);
    const double d0 = lb + e.two_g * b0, d2 = lb + e.two_g * b2;
    const double dl = (a0 * s[0] + a2 * s[2] - k.c_cos_phi) / (a0 * d0 + a2 * d2);
    const Vec3 s_p(s[0] - dl * d0, s[1] - dl * lb, s[2] - dl * d2);
    if (s_p[0] <= s_p[1] && s_p[1] <= s_p[2]) {
      s = s_p;
      ep = Vec3(dl * b0, 0.0, dl * b2);
      done = true;
    }
  }
  if (!done) r = mohr_coulomb_return(e, k, sq, s, ep);
  if (region) *region = r;
  if (r == MohrCoulombRegion::Elastic) {  // admissible within the tolerance after all
    stress = trial;
    state.yielding = 0;
    return V::Zero();
  }
  double sv[3], ev[3];  // returned values and plastic strains per slot
  for (int i = 0; i < 3; ++i) {
    sv[pp.slot[i]] = s[i];
    ev[pp.slot[i]] = ep[i];
  }
  stress = pp.rebuild<V>(sv);
  record_plastic_strain(ep, state);
  return pp.rebuild<V>(ev);
}

// The elastic check: f <= tol and sigma_3 - t <= tol, relative to the stress magnitude.
SKRED_INLINE bool mohr_coulomb_admissible(const MohrCoulombConstants& k, const Vec3& p, double tol) {
  const double scale = k.c_cos_phi + std::max(std::abs(p[0]), std::abs(p[2]));
  return mohr_coulomb_yield(k, p) <= tol * scale &&
         p[2] - k.tension_cutoff <= tol * (scale + std::abs(k.tension_cutoff));
}

// A sufficient elastic condition from p and J2 alone (no eigenvalues, no square root). With
// a = (sigma_3 - sigma_1)/2 and m = s_2 (the middle deviatoric value), J2 = a^2 + 3 m^2 / 4 and
// f = a + (p - m/2) sin(phi) - c cos(phi) (eq. 5.1), whose largest value over all Lode angles
// is sqrt(J2) sqrt(1 + sin^2(phi)/3) + p sin(phi) - c cos(phi); and sigma_3 <= p + 2 sqrt(J2/3).
// Both bounds below zero: elastic, whatever the Lode angle.
SKRED_INLINE bool clearly_elastic(const MohrCoulombConstants& k, const Sym3& s) {
  constexpr double third = 1.0 / 3.0;  // (a product, not a division: a sufficient check)
  const double p = (s[0] + s[1] + s[2]) * third;
  const double d0 = s[0] - p, d1 = s[1] - p, d2 = s[2] - p;
  const double j2 = 0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
  const double room = k.c_cos_phi - p * k.sin_phi;  // f < 0 needs room > sqrt(J2 (1 + sin^2/3))
  const double cut = k.tension_cutoff - p;          // sigma_3 < t needs cut > sqrt(4 J2 / 3)
  return room > 0.0 && j2 * (1.0 + k.sin_phi * k.sin_phi * third) < room * room && cut > 0.0 &&
         (cut == std::numeric_limits<double>::infinity() || 4.0 * j2 < 3.0 * cut * cut);
}

// The elastic check on bounds of sigma_1 and sigma_3 (principal_bounds): f grows with sigma_3
// and falls with sigma_1 (eq. 5.1), so f(lo, hi) <= 0 and hi <= t make the trial admissible;
// the margin 1e-10 of the stress magnitude covers the round-off of the bounds.
SKRED_INLINE bool elastic_by_bounds(const MohrCoulombConstants& k, const PrincipalBounds& b) {
  return mohr_coulomb_admissible(k, Vec3(b.lo, 0.5 * (b.lo + b.hi), b.hi), -1e-10);
}
}  // namespace detail

// Stress update: `stress` in = sigma^k, out = the returned stress; `deps` = total strain
// increment (tensor components). Returns the plastic strain increment (zero when elastic).
// State: volume_strain += tr(d_eps) always; when plastic plastic_shear_strain +=
// 2 sqrt(J2(d_eps_p)), plastic_volume_strain += tr(d_eps_p), yielding = 1; else yielding = 0.
// `region` (optional) receives the return region.
SKRED_INLINE Sym3 mohr_coulomb_update(const ElasticConstants& e, const MohrCoulombConstants& k, Sym3& stress,
                                      const Sym3& deps, PointState& state,
                                      MohrCoulombRegion* region = nullptr) {
  state.volume_strain += deps[0] + deps[1] + deps[2];
  const Sym3 trial = stress + elastic_increment(e, deps);
  // Screening: exact principal values in plane strain (tolerance kYieldRelTol); in 3D two
  // sufficient checks, from p and J2 alone and from bounds on sigma_1 and sigma_3; near or beyond
  // the surface the plastic path decides with the accurate decomposition. The bounds stop at the
  // first Newton iterate that proves the trial admissible (each is a bound); they are skipped
  // for a point whose last update was plastic: it most likely yields again, where they cost as
  // much as the decomposition (a near-double root slows their Newton steps), and the plastic path
  // finds the same answer for one that turns out elastic.
  if (is_plane(trial)) {
    const PlanePrincipal pp = plane_principal(trial);
    if (detail::mohr_coulomb_admissible(k, Vec3(pp.v[0], pp.v[1], pp.v[2]), kYieldRelTol)) {
      stress = trial;
      state.yielding = 0;
      if (region) *region = MohrCoulombRegion::Elastic;
      return Sym3::Zero();
    }
    return detail::mohr_coulomb_plastic_plane(e, k, stress, trial, pp, state, region);
  }
  const auto admissible = [&k](const PrincipalBounds& b) { return detail::elastic_by_bounds(k, b); };
  if (detail::clearly_elastic(k, trial) ||
      (!state.yielding && admissible(principal_bounds(trial, admissible)))) {
    stress = trial;
    state.yielding = 0;
    if (region) *region = MohrCoulombRegion::Elastic;
    return Sym3::Zero();
  }
  return detail::mohr_coulomb_plastic(e, k, stress, trial, state, region);
}

// Plane strain on the stored components [xx, yy, zz, xy] (the solver's hot path): the same
// update as above with d_eps = (e0, e1, 0, e3). Returns d_eps_p in the same four components.
SKRED_INLINE Eigen::Vector4d mohr_coulomb_update_plane(const ElasticConstants& e,
                                                       const MohrCoulombConstants& k, Eigen::Vector4d& stress,
                                                       double e0, double e1, double e3, PointState& state) {
  const double tr = e0 + e1, lam = e.lambda * tr;
  state.volume_strain += tr;
  const Eigen::Vector4d trial(stress[0] + lam + e.two_g * e0, stress[1] + lam + e.two_g * e1, stress[2] + lam,
                              stress[3] + e.two_g * e3);
  const PlanePrincipal pp = plane_principal(trial);
  if (detail::mohr_coulomb_admissible(k, Vec3(pp.v[0], pp.v[1], pp.v[2]), kYieldRelTol)) {
    stress = trial;
    state.yielding = 0;
    return Eigen::Vector4d::Zero();
  }
  return detail::mohr_coulomb_plastic_plane(e, k, stress, trial, pp, state, nullptr);
}

// The fixed interface: same as above with the derived constants built on the fly.
inline Sym3 mohr_coulomb_update(const ElasticConstants& e, const MohrCoulombParams& mc, Sym3& stress,
                                const Sym3& deps, PointState& state) {
  return mohr_coulomb_update(e, MohrCoulombConstants(mc), stress, deps, state);
}

}  // namespace skred
