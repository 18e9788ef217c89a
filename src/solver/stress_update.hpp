// The stress update of one material point from a grid velocity gradient.
#pragma once
#include "core/types.hpp"
#include "material/material.hpp"

namespace skred {

// Symmetric part of a D x D tensor embedded in 3D Voigt form (plane strain: zero
// out-of-plane components).
template <int D> [[gnu::always_inline]] inline Sym3 sym_voigt(const Mat<D>& a) {
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

// The D x D block of a symmetric 3D tensor in Voigt form.
template <int D> [[gnu::always_inline]] inline Mat<D> sym_block(const Sym3& s) {
  if constexpr (D == 2) {
    Mat<2> m;
    m << s[0], s[3], s[3], s[1];
    return m;
  } else {
    return to_matrix(s);
  }
}

// Push-forward sigma = dF S dF^T / det(dF) (Thesis eq. 4.4).
template <int D> [[gnu::always_inline]] inline Sym3 push_forward(const Mat<D>& dF, const Sym3& S) {
  if constexpr (D == 2) {
    const double J = dF.determinant();
    Mat<2> s2;
    s2 << S[0], S[3], S[3], S[1];
    const Mat<2> r = dF * s2 * dF.transpose() / J;
    Sym3 out;
    out << r(0, 0), r(1, 1), S[2] / J, 0.5 * (r(0, 1) + r(1, 0)), 0.0, 0.0;
    return out;
  } else {
    return to_voigt(dF * to_matrix(S) * dF.transpose() / dF.determinant());
  }
}

struct StressUpdateResult {
  double strain_energy = 0.0;  // stored: V (sigma^{k+1} + sigma^k)/2 : (d_eps - d_eps_p)  (eq. 4.16)
  double dissipation = 0.0;    // plastic work V (sigma^{k+1} + sigma^k)/2 : d_eps_p
};

// Objective stress update through the deformation-gradient increment (Thesis eq. 4.1-4.4):
// d_eps = dt sym(grad v) (eq. 2.20), S^{k+1} = sigma^k + C : d_eps and the plastic return
// (eq. 4.2-4.3, 5.2-5.4, done by the material), sigma^{k+1} = dF S dF^T / det dF with
// dF = I + dt grad v (eq. 3.5, 4.4). `dF_step` accumulates the increment of this time step;
// `Fe` is the elastic part of F, updated by Fe <- (I + d_eps - d_eps_p) Fe (Post eq. 72-73);
// `volume` is the current volume. The trapezoidal stress work splits exactly into the
// stored (elastic) part and the plastic dissipation.
template <int D>
[[gnu::always_inline]] inline StressUpdateResult update_point_stress(const Material& mat, const Mat<D>& grad_v, double dt,
                                              double volume, Sym3& stress, PointState& state,
                                              Mat<D>& dF_step, Mat<D>& Fe) {
  const Mat<D> G = dt * grad_v;
  const Sym3 deps = sym_voigt<D>(G);
  const Sym3 old = stress;
  const Sym3 deps_p = update_stress(mat, stress, deps, state);
  const Mat<D> dF = Mat<D>::Identity() + G;
  stress = push_forward<D>(dF, stress);
  dF_step = dF * dF_step;
  const Sym3 deps_e = deps - deps_p;
  Fe = (Mat<D>::Identity() + sym_block<D>(deps_e)) * Fe;
  const Sym3 mid = 0.5 * volume * (old + stress);
  return {contract(mid, deps_e), contract(mid, deps_p)};
}

}  // namespace skred
