// Multi-continuum frictional contact (Paper III §C.2.7, eq. C.36; Bardenhagen et al. 2000,
// 2001; York et al. 1999): the rules of a scenario's contacts and the Coulomb rule at one
// grid node for one pair of continua. The phase that applies it is contact.cpp.
#pragma once
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/types.hpp"

namespace skred {

// At most this many bodies take part in a run with contact (each has its own grid fields).
inline constexpr int kMaxContactBodies = 32;

// Friction coefficient that marks a bonded pair: the two bodies share one velocity at their
// common nodes, as every body does without contact.
inline constexpr double kBonded = -1.0;

// The contact rules of a run. Empty (no bodies): one centre-of-mass velocity field for all.
template <int D>
struct ContactSettings {
  // Per body id: rigid (prescribed constant velocity `rigid_velocity`, no stress update).
  std::vector<char> rigid;
  std::vector<Vec<D>> rigid_velocity;
  // mu for each pair (a, b), row-major n x n and symmetric; kBonded for bonded pairs.
  std::vector<double> friction;
  // Body ids in the master-slave hierarchy (Paper III §C.2.7): order[0] is the master.
  std::vector<int> order;

  int bodies() const { return static_cast<int>(rigid.size()); }
  bool enabled() const { return !rigid.empty(); }
  double mu(int a, int b) const { return friction[static_cast<std::size_t>(a * bodies() + b)]; }
  // n bodies, deformable, all pairs bonded, hierarchy in id order.
  void resize(int n) {
    rigid.assign(static_cast<std::size_t>(n), 0);
    rigid_velocity.assign(static_cast<std::size_t>(n), Vec<D>::Zero());
    friction.assign(static_cast<std::size_t>(n * n), kBonded);
    order.clear();
    for (int b = 0; b < n; ++b) order.push_back(b);
  }
  void set_friction(int a, int b, double mu) {
    friction[static_cast<std::size_t>(a * bodies() + b)] = mu;
    friction[static_cast<std::size_t>(b * bodies() + a)] = mu;
  }
};

// What one pair's contact took out of the nodal kinetic energy (>= 0 by construction).
struct ContactLoss {
  double normal = 0.0;    // the inelastic stop of the approach: 1/2 m_r w_n^2
  double friction = 0.0;  // friction impulse times the mean slip speed
};

// Coulomb contact between continua a (higher in the hierarchy) and b at one node (Paper III
// §C.2.7, after Bardenhagen et al. 2000, in velocity form). v_a, v_b: the trial
// end-of-step velocities of the two continua with nodal masses m_a, m_b (inf: rigid); n:
// b's outward unit normal (pointing into a). With w = v_b - v_a, the pair
// approaches when w.n > 0; the normal contact force that stops this, m_r w.n / dt with
// m_r = m_a m_b / (m_a + m_b), is then compressive (t_n < 0), otherwise the continua
// separate freely. Friction is bounded by mu times it: the tangential relative motion stops
// within the step (stick) when m_r |w_t| <= mu m_r w.n, otherwise it slips with the full
// friction impulse against the sliding direction. Equal and opposite impulses: momentum is
// conserved; |w| only decreases: kinetic energy is never created. mu = kBonded: the pair
// shares one velocity (no separation, no slip).
template <int D>
inline ContactLoss resolve_pair(Vec<D>& v_a, double m_a, Vec<D>& v_b, double m_b, const Vec<D>& n,
                                double mu) {
  ContactLoss loss;
  if (std::isinf(m_a) && std::isinf(m_b)) return loss;  // two rigid bodies
  const double m_r = std::isinf(m_a) ? m_b : std::isinf(m_b) ? m_a : m_a * m_b / (m_a + m_b);
  const Vec<D> w = v_b - v_a;
  Vec<D> dw;       // change of the relative velocity
  if (mu < 0.0) {  // bonded
    dw = -w;
    loss.normal = 0.5 * m_r * w.squaredNorm();
  } else {
    const double wn = w.dot(n);
    if (!(wn > 0.0)) return loss;  // separating, or at rest along n: free
    const Vec<D> wt = w - wn * n;
    const double st = wt.norm();
    const double stop = mu * wn;                    // tangential speed friction can take out in this step
    const double s = st <= stop ? 1.0 : stop / st;  // fraction of the slip removed
    dw = -wn * n - s * wt;
    loss.normal = 0.5 * m_r * wn * wn;
    loss.friction = 0.5 * m_r * st * st * s * (2.0 - s);  // = m_r s st (st + (1 - s) st) / 2
  }
  // Impulse on b: m_r dw; on a: the opposite (a rigid body's infinite mass takes it unmoved).
  v_b += (m_r / m_b) * dw;
  v_a -= (m_r / m_a) * dw;
  return loss;
}

}  // namespace skred
