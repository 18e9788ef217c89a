// Multi-continuum frictional contact (Paper III §C.2.7, eq. C.36; Bardenhagen et al. 2000,
// 2001; York et al. 1999): the rules of a scenario's contacts and the Coulomb rule at one
// grid node for one pair of continua. The phase that applies it is contact.cpp.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

#include "core/types.hpp"

namespace skred {

// At most this many bodies take part in a run with contact (each has its own grid fields).
inline constexpr int kMaxContactBodies = 32;

// Volume check of contact detection (Nairn 2013): the fraction of a node's support the
// continua there must fill together to be in contact. Checked: R3's discs (ContactDiscs)
// keep their energy to 0.05 % with it, and lose 9 % (stopped a cell and more before they
// touch) or become unstable as they part without it.
inline constexpr double kContactFill = 0.8;

// How a pair with a [[contact]] entry decides, at a node where both have mass and approach,
// that it is in contact (docs/method.md, "Contact detection"). Fill: together the continua
// at the node fill kContactFill of its support (Nairn 2013). Traction (Paper III §C.2.7,
// Bardenhagen et al. 2001): the normal traction of the pair's nodal stresses is not tensile,
// n . (S^a + S^b) . n <= 0 with S^c = sum_p N_ip m_p sigma_p of continuum c (traction_at).
enum class ContactDetection : char { Fill, Traction };

// A dilated continuum (Paper III §C.3.2) that fills less than this fraction of the support of
// every node within two nodes of a node (per axis) moves with its parent at the node, as if
// its points had not left it: it has contact of its own only as a region about two cells
// across (which fills its inner nodes entirely). Alone, or as a string or band one cell
// thick (at most 0.11 of a node for a lone point with 3 x 3 points per cell, 0.25 for a cell
// full of them, 0.5 for a band a cell thick), a point in its own continuum has too few
// neighbours to balance its stress, whose nodal forces the mass-gradient normals of the
// sand around it turn into a net push: in Rubjerg Knude such points reached 50-150 m/s and
// the run became unstable with 0.3 (and with no limit).
inline constexpr double kDilatedFill = 0.6;

// Friction coefficient that marks a bonded pair: the two bodies share one velocity at their
// common nodes, as every body does without contact.
inline constexpr double kBonded = -1.0;

// The contact rules of a run. Empty (no bodies): one centre-of-mass velocity field for all.
template <int D>
struct ContactSettings {
  // Per body id: rigid (prescribed constant velocity `rigid_velocity`, no stress update).
  std::vector<char> rigid;
  std::vector<Vec<D>> rigid_velocity;
  // Per body id (may be empty): the outward unit normal of a fixed rigid body's outline at a
  // point, or zero where it has none (the scenario's shape_normal). Where such a body is in
  // contact its exact normal replaces the mass gradient's (docs/method.md, "Contact").
  std::vector<std::function<Vec<D>(const Vec<D>&)>> outline_normal;
  // mu for each pair (a, b), row-major n x n and symmetric; kBonded for bonded pairs.
  std::vector<double> friction;
  // Body ids in the master-slave hierarchy (Paper III §C.2.7): order[0] is the master.
  std::vector<int> order;
  // Per body id (may be empty): the body a dilated continuum takes its points from (Paper III
  // §C.3.2), else -1. The two share one volume per mass (ExplicitSolver::volume_per_mass), from
  // the points of both, which stays the same as points move from one to the other (and is there
  // while the continuum is empty).
  std::vector<int> parent;
  // Per pair (row-major n x n, symmetric): 1 where the pair decides by the traction rule
  // (ContactDetection::Traction), else 0 (the fill rule; bonded pairs keep it).
  std::vector<char> traction;

  int bodies() const { return static_cast<int>(rigid.size()); }
  bool enabled() const { return !rigid.empty(); }
  double mu(int a, int b) const { return friction[static_cast<std::size_t>(a * bodies() + b)]; }
  // n bodies, deformable, all pairs bonded, hierarchy in id order.
  void resize(int n) {
    rigid.assign(static_cast<std::size_t>(n), 0);
    rigid_velocity.assign(static_cast<std::size_t>(n), Vec<D>::Zero());
    outline_normal.assign(static_cast<std::size_t>(n), {});
    friction.assign(static_cast<std::size_t>(n * n), kBonded);
    parent.assign(static_cast<std::size_t>(n), -1);
    traction.assign(static_cast<std::size_t>(n * n), 0);
    order.clear();
    for (int b = 0; b < n; ++b) order.push_back(b);
  }
  void set_friction(int a, int b, double mu) {
    friction[static_cast<std::size_t>(a * bodies() + b)] = mu;
    friction[static_cast<std::size_t>(b * bodies() + a)] = mu;
  }
  void set_detection(int a, int b, ContactDetection rule) {
    const char t = rule == ContactDetection::Traction;
    traction[static_cast<std::size_t>(a * bodies() + b)] = t;
    traction[static_cast<std::size_t>(b * bodies() + a)] = t;
  }
  bool by_traction(int a, int b) const { return traction[static_cast<std::size_t>(a * bodies() + b)] != 0; }
  bool any_traction() const { return std::find(traction.begin(), traction.end(), 1) != traction.end(); }
};

// n . S . n for the mass-weighted nodal stress sums of a continuum (or of a pair, added),
// kept as the diagonal (xx, yy[, zz]) and the off-diagonal part ((xy, 0) in 2D, (yz, xz, xy)
// in 3D): its sign is that of the normal traction of the mean stress S / m.
template <int D>
inline double traction_at(const Vec<D>& diagonal, const Vec<D>& off, const Vec<D>& n) {
  double t = 0.0;
  for (int d = 0; d < D; ++d) t += diagonal[d] * n[d] * n[d];
  if constexpr (D == 2)
    t += 2.0 * off[0] * n[0] * n[1];
  else
    t += 2.0 * (off[0] * n[1] * n[2] + off[1] * n[0] * n[2] + off[2] * n[0] * n[1]);
  return t;
}

// The work one pair's contact did against the motion in one step (Paper III §C.2.7): the
// impulse J on b (-J on a) times the mean relative velocity over the step, -J . (w^k +
// w^{k+1}) / 2 (the trapezoidal rule for the work of a force that changes the velocity from
// w^k to w^{k+1}). Split by the impulse's normal and tangential (friction) parts. At a
// resting contact (w^k = w^{k+1} = 0) it is zero, however large the contact force.
struct ContactLoss {
  double normal = 0.0;    // the stop of the approach
  double friction = 0.0;  // friction: the tangential impulse times the mean slip, >= 0 per pair
  // The friction term before a pair's negative one is counted as no work (friction_sum - the
  // clipped friction is what that drops), and the kinetic energy of the relative motion the
  // rule took, (1/2) m_r (|w|^2 - |w^{k+1}|^2) >= 0 per pair by construction.
  double friction_sum = 0.0;
  double rule_dissipation = 0.0;
};

// Coulomb contact between continua a (higher in the hierarchy) and b at one node (Paper III
// §C.2.7, after Bardenhagen et al. 2000, in velocity form). v_a, v_b: the trial
// end-of-step velocities of the two continua with nodal masses m_a, m_b (inf: rigid); n:
// b's outward unit normal (pointing into a); w_start: their relative velocity v_b - v_a at
// the start of the step. With w = v_b - v_a, the pair approaches when w.n > 0; the normal
// contact force that stops this, m_r w.n / dt with m_r = m_a m_b / (m_a + m_b), is then
// compressive (t_n < 0), otherwise the continua separate freely. Friction is bounded by mu
// times it: the tangential relative motion stops within the step (stick) when m_r |w_t| <=
// mu m_r w.n, otherwise it slips with the full friction impulse against the sliding
// direction. Equal and opposite impulses: momentum is conserved; |w| only decreases.
// mu = kBonded: the pair shares one velocity (no separation, no slip).
template <int D>
inline ContactLoss resolve_pair(Vec<D>& v_a, double m_a, Vec<D>& v_b, double m_b, const Vec<D>& n, double mu,
                                const Vec<D>& w_start) {
  ContactLoss loss;
  if (std::isinf(m_a) && std::isinf(m_b)) return loss;  // two rigid bodies
  const double m_r = std::isinf(m_a) ? m_b : std::isinf(m_b) ? m_a : m_a * m_b / (m_a + m_b);
  const Vec<D> w = v_b - v_a;
  Vec<D> dw;       // change of the relative velocity
  if (mu < 0.0) {  // bonded
    dw = -w;
    loss.normal = 0.5 * m_r * w.dot(w_start);  // -J . (w^k + 0) / 2, J = m_r dw
  } else {
    const double wn = w.dot(n);
    if (!(wn > 0.0)) return loss;  // separating, or at rest along n: free
    const Vec<D> wt = w - wn * n;
    const double st = wt.norm();
    const double stop = mu * wn;                    // tangential speed friction can take out in this step
    const double s = st <= stop ? 1.0 : stop / st;  // fraction of the slip removed
    dw = -wn * n - s * wt;
    // -J . (w^k + w^{k+1}) / 2 with J = m_r dw, w^{k+1} = (1 - s) w_t
    loss.normal = 0.5 * m_r * wn * w_start.dot(n);
    // Where the slip reverses within the step (w^k opposite to the trial slip) the rule's one
    // friction direction per step would make this slightly negative; counted as no work.
    loss.friction_sum = 0.5 * m_r * s * (wt.dot(w_start) + (1.0 - s) * st * st);
    loss.friction = std::max(0.0, loss.friction_sum);
  }
  loss.rule_dissipation = 0.5 * m_r * (w.squaredNorm() - (w + dw).squaredNorm());
  // Impulse on b: m_r dw; on a: the opposite (a rigid body's infinite mass takes it unmoved).
  v_b += (m_r / m_b) * dw;
  v_a -= (m_r / m_a) * dw;
  return loss;
}

}  // namespace skred
