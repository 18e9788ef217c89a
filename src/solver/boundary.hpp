// Boundary conditions on the sides of the grid: free, fixed, roller (no normal motion) and
// frictional contact without penalty parameters (Thesis eq. 5.8-5.11, Post eq. 52-55).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/grid.hpp"
#include "solver/boundary_side.hpp"
#include "solver/grid_fields.hpp"
#include "transfer/box_exchange.hpp"
#include "transfer/node_box.hpp"

namespace skred {

// One wall a node lies on (or beyond).
struct Wall {
  int axis = 0;       // axis normal to the wall
  double sign = 1.0;  // outward normal: -1 on the low side, +1 on the high side
  BoundarySide side;
};

// A node on (or beyond) one or more walls (corner nodes touch several), by side index
// (2 axis + 0 low / 1 high): 16 bytes, so the walks over the boundary nodes stay in cache.
struct BoundaryNode {
  std::size_t node = 0;
  std::array<std::uint8_t, 3> walls{};
  std::uint8_t count = 0;
};

// What the walls did to the grid's energy in one step.
struct WallEnergy {
  // Energy the walls took, booked: the nodes' kinetic energy change less the forces' work over
  // the points' mean velocity (v^k + v^{k+1}) / 2, summed over the wall nodes (`work_sum`), and
  // nothing for a step whose sum is negative. Coulomb friction (eq. 5.8-5.11), the no-slip of
  // fixed walls and the stopped normal motion.
  double work = 0.0;
  double work_sum = 0.0;
  // What the wall rules themselves took from the trial velocities, sum (1/2) m (|v_trial|^2 -
  // |v^{k+1}|^2): >= 0 at every node by coulomb_contact's construction.
  double rule_dissipation = 0.0;
  // The nodes' halves of the walls' share of the lumped mass's loss in the particle update,
  // over the boundary nodes, with s_i = GridFields::stopped_acceleration: (1/2) dt^2 sum_i m_i
  // s_i . a_i (the form paired with FLIP and APIC) and (1/2) dt sum_i m_i s_i . v_i^{k+1} (with the
  // PIC share and XPIC). The points' halves: wall_update_loss (explicit_solver_impl.hpp).
  double update_loss_change = 0.0;
  double update_loss_end = 0.0;
  // Per side (2 axis + 0 low / 1 high): whether its nodes' stopped motion had an energy, sum m_i
  // |dt s_i|^2, over 1e-6 of their kinetic energy this step; the points need not read s_i next to
  // a wall that stopped nothing more (a plane-strain slab's rollers).
  std::array<bool, 6> stopping{};
};

template <int D>
class Boundaries {
 public:
  Boundaries() = default;
  // Sides in the order x_min, x_max, y_min, y_max[, z_min, z_max]. The walks over the
  // boundary nodes run on `threads` OpenMP threads once there are enough of them.
  Boundaries(const GridGeometry<D>& g, const std::array<BoundarySide, 2 * D>& sides, int threads = 1);

  // Both walks visit the boundary nodes inside `box`, the nodes the points reach: outside it
  // the grid fields are zero and never read (node_box.hpp). A slab's z walls span the whole
  // grid plane, most of it far from the material.

  // Velocity conditions: fixed -> v = 0, roller -> v_n = 0, friction -> no motion into
  // the wall (separation allowed).
  void constrain_velocity(GridArray<Vec<D>>& velocity, const NodeBox<D>& box) const;

  // End-of-step conditions on the boundary nodes. With v^k the constrained start-of-step
  // velocity, v* = (m v)/m the unconstrained one and accel = (f + m g)/m on entry, sets
  // v^{k+1} from the trial v^k + dt accel (friction: coulomb_friction.hpp), then
  // accel = (v^{k+1} - v*) / dt (so the particles' FLIP update also obeys the wall) and
  // velocity_move = (v^k + v^{k+1}) / 2 and stopped_acceleration = the change of accel. Returns
  // the energy the walls took (WallEnergy): split among processes (`exchange` not null), summed
  // over them, each node counted once (collective).
  WallEnergy constrain_end_of_step(GridFields<D>& grid, double dt, const NodeBox<D>& box,
                                   const BoxExchange<D>* exchange = nullptr) const;

  // Which layers of a point's block of S nodes per axis from flat node `base` lie on (or beyond)
  // a side in `sides` (bit 2 axis + 0 low / 1 high; near_stopping_sides): per axis a bitmask of
  // its S layers, zero on an axis without such a side; false when none does. Table lookups,
  // and the base's index along each axis concerned only: it runs per point.
  template <int S>
  bool block_layers(std::size_t base, unsigned sides, std::array<unsigned, D>& layers) const {
    static_assert(S <= kLayers);
    unsigned any = 0;
    for (int d = 0; d < D; ++d) {
      layers[d] = 0;
      const bool lo = (sides >> (2 * d)) & 1u, hi = (sides >> (2 * d + 1)) & 1u;
      if (!lo && !hi) continue;
      const std::size_t j = axis_index(base, d);
      const unsigned m = (lo ? low_layers_[d][j] : 0u) | (hi ? high_layers_[d][j] : 0u);
      layers[d] = m & ((1u << S) - 1u);
      any |= layers[d];
    }
    return any != 0;
  }

  const std::vector<BoundaryNode>& nodes() const { return nodes_; }
  const Wall& wall(std::uint8_t side) const { return walls_[side]; }

 private:
  std::vector<BoundaryNode> nodes_;
  std::array<Wall, 2 * D> walls_{};  // per side
  int threads_ = 1;
  // Below this many boundary nodes a walk stays on one thread (a 2D grid's few thousand: the
  // fork would cost more than the walk).
  static constexpr std::size_t kParallelNodes = 8192;
  bool parallel() const { return threads_ > 1 && nodes_.size() >= kParallelNodes; }
  // nodes_ (in flat-index order) of the row of nodes r (the flat index divided by the first
  // axis's stride): [row_start_[r], row_start_[r + 1])
  std::vector<std::size_t> row_start_;
  // The range of nodes_ inside `box` in its row r (box_rows): the row's boundary nodes
  // between the box's first and last index along axis 0.
  std::pair<std::size_t, std::size_t> span_in(const NodeBox<D>& box, long r) const;
  // block_layers' tables: per axis and node index j, the bits k < kLayers for which node j + k
  // lies on or beyond the low (high) wall
  static constexpr int kLayers = 4;
  std::array<std::vector<std::uint8_t>, D> low_layers_, high_layers_;
  std::array<std::size_t, D> nodes_per_axis_{};  // nodes along axis d
  std::size_t stride_[D]{};                      // flat-index stride of axis d
  std::array<double, D> inv_nodes_{}, inv_stride_{};
  // floor(a / b) for b with inv_b = 1 / b: by multiplication, corrected (exact to within one)
  static std::size_t quotient(std::size_t a, std::size_t b, double inv_b) {
    std::size_t q = static_cast<std::size_t>(static_cast<double>(a) * inv_b);
    while (q * b > a) --q;
    while ((q + 1) * b <= a) ++q;
    return q;
  }
  // the index along axis d of flat node i
  std::size_t axis_index(std::size_t i, int d) const {
    if (d > 0) i = quotient(i, stride_[d], inv_stride_[d]);
    if (d < D - 1) i -= quotient(i, nodes_per_axis_[d], inv_nodes_[d]) * nodes_per_axis_[d];
    return i;
  }
};

}  // namespace skred
