// Multi-continuum frictional contact (Paper III §C.2.7, eq. C.36): the grid phases of a run
// with contact, where each body (continuum) has its own nodal fields, and the contact phase
// that couples the bodies at the nodes they share. docs/method.md, "Contact".
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "solver/contact.hpp"
#include "solver/explicit_solver.hpp"

namespace skred {

namespace {

// The direction of grad m_i of a nodal mass field at node i: the density gradient that gives
// the contact normals (York et al. 1999), as the derivative of the nodal masses smoothed
// over 5 nodes per axis (binomial weights 1-4-6-4-1, their derivative -1-2-0-2-1 along the
// axis; nodes beyond the grid's edge left out). The smoothing keeps the normals of a sloped
// surface, which the points resolve as a staircase, within a few degrees.
template <int D>
Vec<D> mass_gradient(const GridGeometry<D>& g, const double* __restrict mass, std::size_t i,
                     const std::array<int, D>& ij) {
  constexpr int R = 2, W = 2 * R + 1;
  constexpr double smooth[W] = {1, 4, 6, 4, 1}, slope[W] = {-1, -2, 0, 2, 1};
  constexpr int count = D == 2 ? W * W : W * W * W;
  Vec<D> grad = Vec<D>::Zero();
  for (int o = 0; o < count; ++o) {
    int k[D];
    long j = static_cast<long>(i);
    bool inside = true;
    for (int d = 0, r = o; d < D; ++d, r /= W) {
      k[d] = r % W;
      const int node = ij[d] + k[d] - R;
      inside = inside && node >= 0 && node < g.nodes(d);
      j += (k[d] - R) * static_cast<long>(g.stride(d));
    }
    if (!inside) continue;
    const double m = mass[j];
    if (m == 0.0) continue;
    for (int d = 0; d < D; ++d) {
      double w = slope[k[d]];
      for (int e = 0; e < D; ++e)
        if (e != d) w *= smooth[k[e]];
      grad[d] += w * m;
    }
  }
  return grad;
}

// The largest nodal mass within two nodes of node i along every axis (nodes beyond the
// grid's edge left out): a region of points fills some node near each of its nodes; a lone
// point fills none.
template <int D>
double nearby_max_mass(const GridGeometry<D>& g, const double* __restrict mass, std::size_t i,
                       const std::array<int, D>& ij) {
  constexpr int R = 2, W = 2 * R + 1;
  constexpr int count = D == 2 ? W * W : W * W * W;
  double most = 0.0;
  for (int o = 0; o < count; ++o) {
    long j = static_cast<long>(i);
    bool inside = true;
    for (int d = 0, r = o; d < D; ++d, r /= W) {
      const int node = ij[d] + r % W - R;
      inside = inside && node >= 0 && node < g.nodes(d);
      j += (r % W - R) * static_cast<long>(g.stride(d));
    }
    if (inside) most = std::max(most, mass[j]);
  }
  return most;
}

}  // namespace

// v_i^k,b = p_i^b / m_i^b under the velocity boundary conditions (eq. 2.23) for each
// deformable body; a rigid body's prescribed velocity wherever it has mass. Then the contact
// rule on these velocities (couple_start), which the strain increment and the motion use.
template <int D>
void ExplicitSolver<D>::body_nodal_velocity() {
  const ContactSettings<D>& c = settings_.contact;
  for (int b = 0; b < c.bodies(); ++b) {
    BodyFields<D>& f = bodies_[static_cast<std::size_t>(b)];
    const bool rigid = c.rigid[static_cast<std::size_t>(b)];
    const Vec<D> vr = c.rigid_velocity[static_cast<std::size_t>(b)];
    transfer_.for_box([&](std::size_t i) {
      const double m = f.mass[i];
      f.velocity[i] = !(m > 0.0) ? Vec<D>::Zero() : rigid ? vr : Vec<D>(f.momentum[i] / m);
      f.velocity_shift[i].setZero();
    });
    if (!rigid) boundaries_.constrain_velocity(f.velocity, transfer_.box());
  }
  couple_start([](BodyFields<D>& f) -> GridArray<Vec<D>>& { return f.velocity; }, true);
}

// The contact rule (couple_nodes) on a start-of-step velocity field of the bodies (v_i^k or
// the remapped v~_i): the single-field scheme's shared nodal velocity where the continua are
// in contact (Bardenhagen et al. 2000 apply the rule to v_i^k as well as to v_i^{k+1}). It
// changes what the strain increments and the motion see, not the points' velocities (those
// take only the accelerations, as with one shared field), so it takes no energy from them.
// `shift`: keep the change in velocity_shift, for the contact phase's accelerations.
template <int D>
template <class Field>
void ExplicitSolver<D>::couple_start(Field&& field, bool shift) {
  couple_nodes(
      [&](const BodyFields<D>& f, std::size_t i) { return field(const_cast<BodyFields<D>&>(f))[i]; },
      [&](BodyFields<D>& f, std::size_t i, const Vec<D>& v) {
        Vec<D>& u = field(f)[i];
        if (shift) f.velocity_shift[i] = v - u;
        u = v;
      },
      [&](const BodyFields<D>& f, std::size_t i) { return field(const_cast<BodyFields<D>&>(f))[i]; });
}

// Eq. 2.49, 2.52 for each deformable body on its own: a_i^b = f_i^int,b / m_i^b + g, the
// walls (eq. 5.8-5.11) on its nodes; a rigid body neither accelerates nor meets the walls.
template <int D>
void ExplicitSolver<D>::body_grid_update() {
  const ContactSettings<D>& c = settings_.contact;
  const bool pic = transfer_rule_.forms_velocity_next();
  for (int b = 0; b < c.bodies(); ++b) {
    BodyFields<D>& f = bodies_[static_cast<std::size_t>(b)];
    if (c.rigid[static_cast<std::size_t>(b)]) {
      transfer_.for_box([&](std::size_t i) {
        f.acceleration[i].setZero();
        f.velocity_move[i] = f.velocity[i];
        if (pic) f.velocity_next[i] = f.velocity[i];
      });
      continue;
    }
    continuum_grid_update(f);  // damped (equilibrium stage) on its own nodes only
  }
}

// v~_i^b = p~_i^b / m_i^b under the velocity conditions for each deformable body (a rigid
// body: its velocity): the remap of its points' velocities, which took the contact
// correction in g2p, then the contact rule on them (couple_start); m_i^b, p_i^b and p~_i^b
// cleared behind for the next step's map.
template <int D>
void ExplicitSolver<D>::body_remap_velocity() {
  const ContactSettings<D>& c = settings_.contact;
  for (int b = 0; b < c.bodies(); ++b) {
    BodyFields<D>& f = bodies_[static_cast<std::size_t>(b)];
    const bool rigid = c.rigid[static_cast<std::size_t>(b)];
    const Vec<D> vr = c.rigid_velocity[static_cast<std::size_t>(b)];
    transfer_.for_box([&](std::size_t i) {
      const double m = f.mass[i];
      f.velocity_remap[i] = !(m > 0.0) ? Vec<D>::Zero() : rigid ? vr : Vec<D>(f.momentum_remap[i] / m);
    });
    if (!rigid) boundaries_.constrain_velocity(f.velocity_remap, transfer_.box());
  }
  couple_start([](BodyFields<D>& f) -> GridArray<Vec<D>>& { return f.velocity_remap; }, false);
  for (BodyFields<D>& f : bodies_)
    transfer_.for_box([&](std::size_t i) {
      f.mass[i] = 0.0;
      f.momentum[i].setZero();
      f.momentum_remap[i].setZero();
    });
}

template <int D>
void ExplicitSolver<D>::clear_body_mass_momentum() {
  for (BodyFields<D>& f : bodies_)
    transfer_.for_box([&](std::size_t i) {
      f.mass[i] = 0.0;
      f.momentum[i].setZero();
    });
}

// Paper III §C.2.7. A node is an interface node when more than one continuum has mass there
// (where v_i^CM - v_i^c != 0 can hold, eq. C.36). The continua present are taken in the
// order of the hierarchy: the master's outward normal is minus its mass gradient, the
// second's is the opposite, n = grad m^1 / |grad m^1|, and continuum k's is the normalised
// gradient of the combined mass of the k - 1 before it (York et al. 1999; Paper III); a
// rigid body with an outline gives its exact normal instead (prepare_contact). Each
// pair (j, k), j < k, is then resolved with k's normal by the Coulomb rule of resolve_pair
// (contact.hpp) on the velocities get(f, i) of the bodies' fields f at node i; set(f, i, v)
// stores the result of each deformable body. Equal and opposite impulses: momentum is
// conserved to round-off; kinetic energy only decreases. Returns the loss summed over nodes.
template <int D>
template <class Get, class Set, class Start>
ContactLoss ExplicitSolver<D>::couple_nodes(Get&& get, Set&& set, Start&& start) {
  const ContactSettings<D>& c = settings_.contact;
  const GridGeometry<D>& g = grid();
  // A rigid body moving at its constant velocity with an outline: its outline normal at node i,
  // that of the shape as built, translated by v t (its points have moved by v dt each step, and
  // are where the step found them: at v times the time of the step's start).
  const auto moving_outline = [&](std::size_t b) {
    return c.rigid[b] && b < c.outline_normal.size() && c.outline_normal[b] &&
           c.rigid_velocity[b].squaredNorm() > 0.0;
  };
  const auto moving_outline_normal = [&](std::size_t b, std::size_t i) {
    return c.outline_normal[b](Vec<D>(g.node_position(i) - state_.clock.time * c.rigid_velocity[b]));
  };
  constexpr std::size_t kPad = 16;  // one cache line of sums per thread
  const BoxExchange<D>* exchange = transfer_.exchange();
  std::fill(contact_sums_.begin(), contact_sums_.end(), 0.0);
  // The rule at node i; `traction`: some pair decides by the traction rule (a compile-time
  // flag, so that the fill rule's loop carries none of its work).
  const auto node = [&](std::size_t i, auto traction_tag) {
    constexpr bool traction = decltype(traction_tag)::value;
    // The continua with mass at node i, in hierarchy order.
    int present[kMaxContactBodies];
    int count = 0;
    for (int b : c.order)
      if (bodies_[static_cast<std::size_t>(b)].mass[i] > 0.0) present[count++] = b;
    if (count < 2) return;
    Vec<D> v[kMaxContactBodies], v0[kMaxContactBodies], grad[kMaxContactBodies], outline[kMaxContactBodies];
    [[maybe_unused]] Vec<D> sd[kMaxContactBodies], so[kMaxContactBodies];  // the traction rule's S_i^b
    double m[kMaxContactBodies];
    const auto ij = g.unflatten(i);
    for (int k = 0; k < count; ++k) {
      const auto b = static_cast<std::size_t>(present[k]);
      const BodyFields<D>& f = bodies_[b];
      m[k] = c.rigid[b] ? INFINITY : f.mass[i];
      v[k] = c.rigid[b] ? c.rigid_velocity[b] : get(f, i);
      v0[k] = c.rigid[b] ? c.rigid_velocity[b] : start(f, i);
      grad[k] = mass_gradient<D>(g, f.mass.data(), i, ij);
      outline[k] = !outline_normals_[b].empty() ? outline_normals_[b][i]
                   : moving_outline(b)          ? moving_outline_normal(b, i)
                                                : Vec<D>::Zero();
      if constexpr (traction) {
        sd[k] = c.rigid[b] ? Vec<D>::Zero() : f.stress_diagonal[i];
        so[k] = c.rigid[b] ? Vec<D>::Zero() : f.stress_off[i];
      }
    }
    // Volume check (Nairn 2013): the continua are in contact at the node only when together
    // they fill kContactFill of its support (h^D, halved per axis at a wall node). Nodes
    // merely within reach of both (GIMP reaches 2.5 cells across a diagonal gap) would stop
    // the approach of bodies that have not met yet.
    double support = 1.0;
    for (int d = 0; d < D; ++d)
      support *=
          (ij[d] <= GridGeometry<D>::pad || ij[d] >= g.cells[d] + GridGeometry<D>::pad) ? 0.5 * g.h : g.h;
    double volume = 0.0;
    for (int k = 0; k < count; ++k)
      volume += bodies_[static_cast<std::size_t>(present[k])].mass[i] *
                volume_per_mass_[static_cast<std::size_t>(present[k])];
    // A dilated continuum (Paper III §C.3.2) that fills less than kDilatedFill of the support
    // of every node within two (nearby_max_mass) moves with its parent at this node: merged into it
    // (mass, momentum and mass gradient added; the velocities joined as a bonded pair's), and given its
    // velocity after the contact rule. `merged` maps the continua present (`ids`) to the entries resolved.
    int ids[kMaxContactBodies], merged[kMaxContactBodies];
    const int all = count;
    ContactLoss sum;
    bool any_merged = false;
    for (int k = 0; k < all; ++k) ids[k] = present[k], merged[k] = k;
    for (int k = 0; k < all && !c.parent.empty(); ++k) {
      const auto b = static_cast<std::size_t>(ids[k]);
      if (c.parent[b] < 0 || nearby_max_mass<D>(g, bodies_[b].mass.data(), i, ij) * volume_per_mass_[b] >=
                                 kDilatedFill * support)
        continue;
      int j = 0;
      while (j < all && ids[j] != c.parent[b]) ++j;
      if (j == all) continue;  // the parent is not here
      const double M = m[j] + m[k];
      sum.normal += 0.5 * m[j] * m[k] / M * Vec<D>(v[k] - v[j]).dot(v0[k] - v0[j]);  // as a bonded pair
      v[j] = (m[j] * v[j] + m[k] * v[k]) / M;
      v0[j] = (m[j] * v0[j] + m[k] * v0[k]) / M;
      grad[j] += grad[k];
      if constexpr (traction) sd[j] += sd[k], so[j] += so[k];
      m[j] = M;
      merged[k] = j;
      any_merged = true;
    }
    if (any_merged) {  // compact the entries left, in hierarchy order
      int slot[kMaxContactBodies];
      count = 0;
      for (int k = 0; k < all; ++k)
        if (merged[k] == k) slot[k] = count++;
      for (int k = 0; k < all; ++k)
        if (merged[k] == k) {
          const int n = slot[k];  // <= k: in place
          present[n] = ids[k], m[n] = m[k], v[n] = v[k], v0[n] = v0[k], grad[n] = grad[k],
          outline[n] = outline[k];
          if constexpr (traction) sd[n] = sd[k], so[n] = so[k];
        }
      for (int k = 0; k < all; ++k) merged[k] = slot[merged[k]];
    }
    // The fill rule's check (above); a pair under the traction rule (ContactDetection) checks
    // its own nodal stresses instead, below.
    const bool filled = volume >= kContactFill * support;
    if (!any_merged && !filled && !traction) return;
    Vec<D> upper = grad[0];  // gradient of the combined mass of the continua above k
    for (int k = 1; k < count; ++k) {
      // A fixed rigid body's outline gives the exact normal: its own as continuum k, or the
      // master's (n = -n^1) for the second continuum at the node.
      const Vec<D> exact = outline[k].squaredNorm() > 0.0 ? outline[k]
                           : k == 1                       ? Vec<D>(-outline[0])
                                                          : Vec<D>::Zero();
      const double len = exact.squaredNorm() > 0.0 ? 1.0 : upper.norm();
      const Vec<D> n = exact.squaredNorm() > 0.0 ? exact : len > 0.0 ? Vec<D>(upper / len) : Vec<D>::Zero();
      for (int j = 0; j < k; ++j) {
        const double mu = c.mu(present[j], present[k]);
        if (mu >= 0.0 && !(len > 0.0)) continue;  // no normal: no contact to resolve
        // Traction rule (Paper III §C.2.7): no contact where the pair's normal traction is
        // tensile; stress-free (the first touch) counts as compressive (Bardenhagen et al. 2001).
        const bool by_traction = traction && mu >= 0.0 && c.by_traction(present[j], present[k]);
        const bool detected =
            by_traction ? traction_at<D>(Vec<D>(sd[j] + sd[k]), Vec<D>(so[j] + so[k]), n) <= 0.0 : filled;
        if (!detected) continue;
        const ContactLoss loss = resolve_pair<D>(v[j], m[j], v[k], m[k], n, mu, Vec<D>(v0[k] - v0[j]));
        sum.normal += loss.normal;
        sum.friction += loss.friction;
        sum.friction_sum += loss.friction_sum;
        sum.rule_dissipation += loss.rule_dissipation;
      }
      upper += grad[k];
    }
    for (int k = 0; k < all; ++k) {
      const auto b = static_cast<std::size_t>(ids[k]);
      if (!c.rigid[b]) set(bodies_[b], i, v[merged[k]]);
    }
    if (exchange && !exchange->counts(i)) return;  // another process's node in the totals
    double* s = &contact_sums_[kPad * static_cast<std::size_t>(omp_get_thread_num())];
    s[0] += sum.normal;
    s[1] += sum.friction;
    s[2] += sum.friction_sum;
    s[3] += sum.rule_dissipation;
  };
  if (contact_traction_)
    transfer_.for_box([&](std::size_t i) { node(i, std::true_type{}); });
  else
    transfer_.for_box([&](std::size_t i) { node(i, std::false_type{}); });
  ContactLoss total;
  for (std::size_t t = 0; t < contact_sums_.size(); t += kPad) {
    total.normal += contact_sums_[t];
    total.friction += contact_sums_[t + 1];
    total.friction_sum += contact_sums_[t + 2];
    total.rule_dissipation += contact_sums_[t + 3];
  }
  sum_points(total.normal, total.friction, total.friction_sum,
             total.rule_dissipation);  // every process's nodes
  return total;
}

// The contact phase (Paper III §C.2.7): couple_nodes on the trial end-of-step velocities
// v_i^k,b + dt a_i^b (after the walls; v_i^k,b as coupled by body_nodal_velocity); the
// coupled velocity v_i^{k+1,b} gives each body's a_i^b = (v_i^{k+1,b} - v_i^k,b) / dt, which
// its points take in g2p, v_move and v_next. The contact work is the work of the impulses
// against the mean velocities of the step (ContactLoss).
template <int D>
void ExplicitSolver<D>::contact() {
  if (!contact_on()) return;
  timer_.time(Phase::Contact, [&] {
    const double dt = settings_.dt;
    const bool pic = transfer_rule_.forms_velocity_next();
    // v_i^k,b as the points' accelerations see it: the mapped velocity, not the coupled one
    const auto base = [](const BodyFields<D>& f, std::size_t i) {
      return Vec<D>(f.momentum[i] / f.mass[i] + f.velocity_shift[i]);
    };
    const ContactLoss loss = couple_nodes(
        [&](const BodyFields<D>& f, std::size_t i) { return Vec<D>(base(f, i) + dt * f.acceleration[i]); },
        [&](BodyFields<D>& f, std::size_t i, const Vec<D>& v) {
          f.acceleration[i] = (v - base(f, i)) / dt;
          f.velocity_move[i] = 0.5 * (f.velocity[i] + v);
          if (pic) f.velocity_next[i] = v;
        },
        [](const BodyFields<D>& f, std::size_t i) { return f.velocity[i]; });
    contact_step_ = loss;
    state_.clock.energy.contact_work += loss.normal + loss.friction;
  });
}

// Each body's reference volume per unit mass, from its points.
template <int D>
void ExplicitSolver<D>::prepare_contact() {
  const ContactSettings<D>& c = settings_.contact;
  std::vector<double> mass(static_cast<std::size_t>(c.bodies()), 0.0), volume(mass);
  const auto& P = state_.points;
  // A dilated continuum's points count with its parent's (Paper III §C.3.2).
  const auto family = [&](std::size_t b) {
    return b < c.parent.size() && c.parent[b] >= 0 ? static_cast<std::size_t>(c.parent[b]) : b;
  };
  for (std::size_t p = 0; p < P.size(); ++p) {
    const auto b = static_cast<std::size_t>(P.body[p]);
    if (b >= mass.size()) continue;
    mass[family(b)] += P.mass[p];
    volume[family(b)] += P.volume0[p];
  }
  state_.processes.sum(mass.data(), mass.size());  // every process's points
  state_.processes.sum(volume.data(), volume.size());
  contact_traction_ = c.any_traction();
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    BodyFields<D>& f = bodies_[b];
    f.velocity_shift.resize(grid().node_count());
    if (contact_traction_ && !c.rigid[b]) {
      f.stress_diagonal.resize(grid().node_count());
      f.stress_off.resize(grid().node_count());
    }
  }
  volume_per_mass_.assign(mass.size(), 0.0);
  for (std::size_t b = 0; b < mass.size(); ++b)
    volume_per_mass_[b] = mass[family(b)] > 0.0 ? volume[family(b)] / mass[family(b)] : 0.0;
  // The outline normals of the fixed rigid bodies at every node, once (they do not move).
  outline_normals_.assign(mass.size(), {});
  for (std::size_t b = 0; b < mass.size() && b < c.outline_normal.size(); ++b) {
    if (!c.rigid[b] || !c.outline_normal[b] || c.rigid_velocity[b].squaredNorm() > 0.0) continue;
    std::vector<Vec<D>>& n = outline_normals_[b];
    n.resize(grid().node_count());
    for (std::size_t i = 0; i < n.size(); ++i) n[i] = c.outline_normal[b](grid().node_position(i));
  }
}

// The rigid bodies' points (contact runs): v_p = the body's prescribed velocity.
template <int D>
void ExplicitSolver<D>::rigid_velocity() {
  const ContactSettings<D>& c = settings_.contact;
  auto& P = state_.points;
  const long n = static_cast<long>(P.size());
#pragma omp parallel for num_threads(threads()) schedule(static)
  for (long p = 0; p < n; ++p) {
    const auto b = static_cast<std::size_t>(P.body[p]);
    if (c.rigid[b]) P.v[p] = c.rigid_velocity[b];
  }
}

#define SKRED_CONTACT_PHASES(D)                                \
  template void ExplicitSolver<D>::body_nodal_velocity();      \
  template void ExplicitSolver<D>::body_grid_update();         \
  template void ExplicitSolver<D>::body_remap_velocity();      \
  template void ExplicitSolver<D>::clear_body_mass_momentum(); \
  template void ExplicitSolver<D>::contact();                  \
  template void ExplicitSolver<D>::prepare_contact();          \
  template void ExplicitSolver<D>::rigid_velocity();
SKRED_CONTACT_PHASES(2)
SKRED_CONTACT_PHASES(3)
#undef SKRED_CONTACT_PHASES

}  // namespace skred
