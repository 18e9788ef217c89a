// Coulomb friction at a rigid surface without penalty parameters (Thesis eq. 5.8-5.11, Post
// eq. 52-55), for one node against one surface: a wall of the grid uses it, and so can a
// sloped rigid base.
#pragma once
#include "core/inline.hpp"
#include "core/types.hpp"

namespace skred {

// The end-of-step velocity of a node against a rigid surface of unit outward normal n (from
// the material into the surface) and Coulomb coefficient mu. v_trial is the node's
// end-of-step velocity without the surface, relative to it: v^k + dt (f^int + f^ext) / m in
// both components (eq. 5.9).
//  - Contact is decided by the normal force the surface must exert to stop the motion into
//    it within the step, f_n = m (v_trial . n) / dt: contact iff f_n > 0 (compressive);
//    otherwise the node separates freely (eq. 5.8 and the text before it).
//  - Slip is decided by the tangential force that would stop the trial slip within the step,
//    |f_t| = m |v_t| / dt (the stick force, eq. 5.11), against mu f_n (eq. 5.8): if it is not
//    larger the node sticks (v_t = 0), otherwise full friction mu f_n acts against the trial
//    slip v_t (eq. 5.10): v_t <- v_t (1 - mu f_n / |f_t|).
// Eq. 5.10 as printed takes the friction's direction from the slip at the start of the step,
// v_t^k; where the other forces reverse the slip within the step that direction pushes the
// node along and creates energy. Here friction opposes the trial slip and never exceeds the
// force that stops it, so the result is v_trial less a normal part that stops and a
// tangential part that at most stops: |v| <= |v_trial| and the surface dissipates
// (1/2) m (|v_trial|^2 - |v|^2) >= 0. In velocity terms m and dt cancel.
template <int D>
SKRED_INLINE Vec<D> coulomb_contact(const Vec<D>& v_trial, const Vec<D>& n, double mu) {
  const double vn = v_trial.dot(n);  // m vn / dt = f_n
  if (vn <= 0.0) return v_trial;     // no compressive normal force: separation, no friction
  const Vec<D> vt = v_trial - vn * n;
  const double slip = vt.norm();             // m slip / dt = |f_t|, the stick force (eq. 5.11)
  const double limit = mu * vn;              // m limit / dt = mu f_n (eq. 5.8)
  if (slip <= limit) return Vec<D>::Zero();  // stick (eq. 5.11)
  return Vec<D>((1.0 - limit / slip) * vt);  // slip with full friction (eq. 5.10)
}

}  // namespace skred
