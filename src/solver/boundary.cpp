#include "solver/boundary.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "solver/coulomb_friction.hpp"

namespace skred {

namespace {

// End-of-step velocity at a node on `wall`, given the trial velocity without the wall.
template <int D>
Vec<D> wall_velocity(const Wall& wall, Vec<D> vnew) {
  switch (wall.side.kind) {
    case BoundaryKind::Fixed: return Vec<D>::Zero();
    case BoundaryKind::Roller: vnew[wall.axis] = 0.0; return vnew;
    case BoundaryKind::Friction: {
      Vec<D> n = Vec<D>::Zero();  // outward normal of the wall
      n[wall.axis] = wall.sign;
      return coulomb_contact<D>(vnew, n, wall.side.friction);  // eq. 5.8-5.11
    }
    case BoundaryKind::Free: return vnew;
  }
  return vnew;
}

}  // namespace

template <int D>
Boundaries<D>::Boundaries(const GridGeometry<D>& g, const std::array<BoundarySide, 2 * D>& sides, int threads)
    : threads_(threads) {
  const double tol = 1e-9 * g.h;
  for (int d = 0; d < D; ++d) {
    walls_[2 * d] = {d, -1.0, sides[2 * d]};
    walls_[2 * d + 1] = {d, +1.0, sides[2 * d + 1]};
  }
  for (int d = 0; d < D; ++d) {
    const int n = g.nodes(d);
    nodes_per_axis_[d] = static_cast<std::size_t>(n);
    inv_nodes_[d] = 1.0 / n;
    stride_[d] = g.stride(d);
    inv_stride_[d] = 1.0 / static_cast<double>(stride_[d]);
    low_layers_[d].assign(static_cast<std::size_t>(n), 0);
    high_layers_[d].assign(static_cast<std::size_t>(n), 0);
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < kLayers && j + k < n; ++k) {
        const double r = g.node_coordinate(d, j + k);
        if (r <= tol) low_layers_[d][static_cast<std::size_t>(j)] |= static_cast<std::uint8_t>(1u << k);
        if (r >= g.h * g.cells[d] - tol)
          high_layers_[d][static_cast<std::size_t>(j)] |= static_cast<std::uint8_t>(1u << k);
      }
  }
  for (std::size_t i = 0; i < g.node_count(); ++i) {
    const auto ij = g.unflatten(i);
    BoundaryNode b;
    b.node = i;
    for (int d = 0; d < D; ++d) {
      const double r = g.node_coordinate(d, ij[d]);
      const BoundarySide& lo = sides[2 * d];
      const BoundarySide& hi = sides[2 * d + 1];
      if (lo.kind != BoundaryKind::Free && r <= tol) b.walls[b.count++] = static_cast<std::uint8_t>(2 * d);
      if (hi.kind != BoundaryKind::Free && r >= g.h * g.cells[d] - tol)
        b.walls[b.count++] = static_cast<std::uint8_t>(2 * d + 1);
    }
    if (b.count > 0) nodes_.push_back(b);
  }
  row_start_.assign(g.node_count() / stride_[1] + 1, 0);
  for (const BoundaryNode& b : nodes_) ++row_start_[b.node / stride_[1] + 1];
  for (std::size_t r = 1; r < row_start_.size(); ++r) row_start_[r] += row_start_[r - 1];
}

template <int D>
std::pair<std::size_t, std::size_t> Boundaries<D>::span_in(const NodeBox<D>& box, long r) const {
  const std::size_t first = box_row_start(box, stride_, r), row = first / stride_[1];
  const auto by_node = [](const BoundaryNode& b, std::size_t i) { return b.node < i; };
  const auto begin = nodes_.begin() + static_cast<long>(row_start_[row]);
  const auto end = nodes_.begin() + static_cast<long>(row_start_[row + 1]);
  const auto lo = std::lower_bound(begin, end, first, by_node);
  const auto hi =
      std::lower_bound(lo, end, first + static_cast<std::size_t>(box.hi[0] - box.lo[0]) + 1, by_node);
  return {static_cast<std::size_t>(lo - nodes_.begin()), static_cast<std::size_t>(hi - nodes_.begin())};
}

template <int D>
void Boundaries<D>::constrain_velocity(GridArray<Vec<D>>& velocity, const NodeBox<D>& box) const {
  const long rows = box_rows(box);
#pragma omp parallel for num_threads(threads_) schedule(static) if (parallel())
  for (long r = 0; r < rows; ++r) {
    const auto [k0, k1] = span_in(box, r);
    for (std::size_t k = k0; k < k1; ++k) {
      const BoundaryNode& b = nodes_[k];
      Vec<D>& v = velocity[b.node];
      for (int w = 0; w < b.count; ++w) {
        const Wall& wall = walls_[b.walls[w]];
        switch (wall.side.kind) {
          case BoundaryKind::Fixed: v.setZero(); break;
          case BoundaryKind::Roller: v[wall.axis] = 0.0; break;
          case BoundaryKind::Friction:
            if (v[wall.axis] * wall.sign > 0.0) v[wall.axis] = 0.0;
            break;
          case BoundaryKind::Free: break;
        }
      }
    }
  }
}

template <int D>
WallEnergy Boundaries<D>::constrain_end_of_step(GridFields<D>& grid, double dt, const NodeBox<D>& box,
                                                const BoxExchange<D>* exchange) const {
  double work = 0.0, rule = 0.0, loss_end = 0.0, loss_change = 0.0;
  double stopped_energy[2 * D] = {}, energy[2 * D] = {};  // per side: sum m |dt s_i|^2, sum m |v_i|^2
  const long rows = box_rows(box);
#pragma omp parallel for num_threads(threads_) schedule(static) if (parallel()) \
    reduction(+ : work, rule, loss_end, loss_change, stopped_energy[:2 * D], energy[:2 * D])
  for (long r = 0; r < rows; ++r) {
    const auto [k0, k1] = span_in(box, r);
    for (std::size_t k = k0; k < k1; ++k) {
      const BoundaryNode& b = nodes_[k];
      const std::size_t i = b.node;
      const double m = grid.mass[i];
      if (m <= 0.0) {
        grid.stopped_acceleration[i].setZero();
        continue;
      }
      const Vec<D> v_free = grid.momentum[i] / m;  // unconstrained start-of-step velocity
      const Vec<D>& v_k = grid.velocity[i];        // v^k: no motion into the walls
      const Vec<D> a = grid.acceleration[i];       // (f^int + f^ext) / m
      // The trial end-of-step velocity (eq. 5.9) from the node's momentum: the normal impulse
      // that stops it at the wall, m (trial . n), is the normal force f_n dt of eq. 5.8 plus
      // the impulse that stops the points' motion into the wall.
      const Vec<D> trial = v_free + dt * a;
      Vec<D> vnew = trial;
      for (int w = 0; w < b.count; ++w) vnew = wall_velocity<D>(walls_[b.walls[w]], vnew);
      // Each wall rule only stops motion (coulomb_friction.hpp).
      assert(vnew.squaredNorm() <= trial.squaredNorm() * (1.0 + 1e-12));
      const double rule_here = 0.5 * m * (trial.squaredNorm() - vnew.squaredNorm());
      // Energy the walls took: the node's kinetic energy change less the work of the forces
      // over the velocity the points move with, (v^k + v^{k+1}) / 2 (eq. 2.55), so that the
      // balance closes with the points' gravity work. Its normal part is (1/2) m (v* . n)^2,
      // the motion into the wall stopped; its tangential part the friction impulse over the
      // mean slip velocity. It can be negative at a node where the forces alone would have
      // reversed its slip within the step (the mean velocity overstates the motion of a node
      // that sticks): summed over the nodes, and a step whose sum is negative takes nothing
      // (clipping each node's instead booked 0.9 % of the soil column's gravity work too much).
      const double taken =
          0.5 * m * (v_free.squaredNorm() - vnew.squaredNorm()) + 0.5 * dt * m * a.dot(v_k + vnew);
      grid.acceleration[i] = (vnew - v_free) / dt;
      // s_i, the stopped motion's acceleration (GridFields::stopped_acceleration)
      Vec<D> stopped = Vec<D>::Zero();
      for (int w = 0; w < b.count; ++w) {
        const Wall& wall = walls_[b.walls[w]];
        if (wall.side.kind == BoundaryKind::Fixed)
          stopped = grid.acceleration[i];
        else
          stopped[wall.axis] = grid.acceleration[i][wall.axis];
        if (wall.side.kind == BoundaryKind::Fixed) break;
      }
      grid.stopped_acceleration[i] = stopped;
      grid.velocity_move[i] = 0.5 * (v_k + vnew);
      if (exchange && !exchange->counts(i)) continue;  // another process's node in the totals
      rule += rule_here;
      work += taken;
      for (int w = 0; w < b.count; ++w) {
        stopped_energy[b.walls[w]] += m * dt * dt * stopped.squaredNorm();
        energy[b.walls[w]] += m * v_free.squaredNorm();
      }
      loss_end += 0.5 * dt * m * stopped.dot(vnew);
      loss_change += 0.5 * dt * m * stopped.dot(vnew - v_free);
    }
  }
  if (exchange) {  // every process's nodes
    double sums[4 + 4 * D] = {work, rule, loss_end, loss_change};
    for (int side = 0; side < 2 * D; ++side)
      sums[4 + side] = stopped_energy[side], sums[4 + 2 * D + side] = energy[side];
    exchange->processes().sum(sums, 4 + 4 * D);
    work = sums[0], rule = sums[1], loss_end = sums[2], loss_change = sums[3];
    for (int side = 0; side < 2 * D; ++side)
      stopped_energy[side] = sums[4 + side], energy[side] = sums[4 + 2 * D + side];
  }
  WallEnergy e;
  e.work = std::max(work, 0.0);
  e.work_sum = work;
  e.rule_dissipation = rule;
  e.update_loss_end = loss_end;
  e.update_loss_change = loss_change;
  // A side stops something when the energy of its stopped motion is not nil against its nodes'
  // kinetic energy (a plane-strain slab's rollers stop a motion of round-off and near-symmetry).
  for (int side = 0; side < 2 * D; ++side) e.stopping[side] = stopped_energy[side] > 1e-6 * energy[side];
  return e;
}

template class Boundaries<2>;
template class Boundaries<3>;

}  // namespace skred
