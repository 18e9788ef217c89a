// The cells of an implicit step for the cell-averaged volumetric strain (B-bar; Hughes 1980, for
// MPM Coombs et al. 2018; the explicit engine's form is solver/volumetric_averaging.hpp): the
// points grouped by the cell that holds them, each cell's box of nodes (the union of its points'
// stencils: S or S + 1 nodes per axis) and its mean divergence operator
//   b_c,j = sum_p V_p m^T B_pj / V_c,   V_c = sum_p V_p,
// m the volumetric axes (in-plane in plane strain, all three in 3D and axisymmetric), so that the
// cell's mean volumetric strain increment is sum_j b_c,j . du_j.
#pragma once
#include <omp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/grid.hpp"
#include "core/particles.hpp"
#include "implicit/point_stencils.hpp"
#include "parallel/processes.hpp"
#include "parallel/star_forest.hpp"
#include "solver/volumetric_averaging.hpp"
#include "transfer/box_exchange.hpp"

namespace skred {

template <int D>
struct CellBoxes {
  static constexpr int kMaxWidth = 5;  // the cubic B-spline's 4 nodes + 1
  int S = 0, K = 0;                    // box width per axis, S^D nodes
  std::vector<std::int32_t> cell;      // per point: its (occupied) cell
  std::vector<std::int32_t> start;     // CSR over the cells: points[start[c] .. start[c + 1])
  std::vector<std::int32_t> points;
  std::vector<std::int64_t> node;   // c K + j: flat grid index of box node j (axis 0 fastest)
  std::vector<std::int32_t> local;  // p Kp + k: box index of point p's stencil node k
  std::vector<double> volume;       // V_c
  std::vector<Vec<D>> mean_div;     // c K + j: b_c,j

  // From the step's stencils (Sp nodes wide), the points' volumes and, in axisymmetric geometry,
  // 1 / r_p (else empty). Returns a point whose stencil does not fit its cell's box (a
  // particle size beyond a cell: no box of S + 1 nodes holds the cell's stencils), or -1.
  //
  // Across processes (issue 55) a process's cells are those its own points occupy, numbered in
  // the grid's order. A cell that several processes' points occupy is shared between them by a
  // star forest of its own (a root at the lowest of them, found over the boxes that hold the
  // cell's lower corner, `boxes`): its box starts at the lowest stencil base of all its points,
  // and V_c and b_c are every process's sums (sum_cells). A process returns its own failing point
  // or -1, and all of them return early alike (the caller agrees on the point).
  long build(const PointStencils<D>& st, int Sp, const GridGeometry<D>& g, const Particles<D>& P,
             const std::vector<double>& point_volume, const std::vector<double>& inv_r, int threads,
             BoxExchange<D>* boxes = nullptr) {
    const std::size_t n = P.size();
    const int Kp = st.K;
    // The occupied cells (one bit per grid cell, by its lower node), numbered in the grid's order.
    // (reset at the previous build's cells alone, which corner_ lists: O(them), not the grid)
    const std::size_t grid_cells = g.node_count();
    if (slot_.size() != grid_cells) {
      occupied_.assign((grid_cells + 63) / 64, 0);
      slot_.assign(grid_cells, -1);
    } else {
      for (const long c : corner_) {
        occupied_[static_cast<std::size_t>(c) / 64] = 0;
        slot_[static_cast<std::size_t>(c)] = -1;
      }
    }
    cell.resize(n);
    for (std::size_t p = 0; p < n; ++p) {
      const std::uint32_t c = VolumetricAveraging<D>::cell_of(g, P.x[p]);
      cell[p] = static_cast<std::int32_t>(c);
      occupied_[c / 64] |= std::uint64_t{1} << (c % 64);
    }
    corner_.clear();
    int cells = 0;
    for (std::size_t w = 0; w < occupied_.size(); ++w)
      for (std::uint64_t bits = occupied_[w]; bits; bits &= bits - 1) {
        const std::size_t c = 64 * w + static_cast<std::size_t>(std::countr_zero(bits));
        slot_[c] = cells++;
        corner_.push_back(static_cast<long>(c));
      }
    for (std::size_t p = 0; p < n; ++p) cell[p] = slot_[static_cast<std::size_t>(cell[p])];
    shared_ = boxes && boxes->processes().distributed();
    if (shared_) share_cells(*boxes);
    // The points grouped by cell (counting sort, in point order).
    start.assign(static_cast<std::size_t>(cells) + 1, 0);
    for (std::size_t p = 0; p < n; ++p) ++start[static_cast<std::size_t>(cell[p]) + 1];
    for (int c = 0; c < cells; ++c) start[c + 1] += start[c];
    points.resize(n);
    {
      std::vector<std::int32_t>& fill = fill_;
      fill.assign(start.begin(), start.end() - 1);
      for (std::size_t p = 0; p < n; ++p) points[fill[cell[p]]++] = static_cast<std::int32_t>(p);
    }
    // Each cell's box starts at its points' lowest stencil base; S = Sp + the largest spread.
    // extent_: per cell, the lowest base and minus the highest per axis (one min over processes).
    extent_.assign(static_cast<std::size_t>(cells) * 2 * D, 1e300);
    for (int c = 0; c < cells; ++c) {
      double* e = &extent_[static_cast<std::size_t>(c) * 2 * D];
      for (int q = start[c]; q < start[c + 1]; ++q) {
        const auto ij =
            g.unflatten(static_cast<std::size_t>(st.node[static_cast<std::size_t>(points[q]) * Kp]));
        for (int d = 0; d < D; ++d)
          e[d] = std::min(e[d], double(ij[d])), e[D + d] = std::min(e[D + d], -double(ij[d]));
      }
    }
    if (shared_)
      for (int k = 0; k < 2 * D; ++k) combine_cells(extent_.data(), 2 * D, k, StarForest::Combine::Min);
    base_.resize(static_cast<std::size_t>(cells));
    int spread = 0;
    long bad = -1;
    bool wide = false;
    for (int c = 0; c < cells; ++c) {
      const double* e = &extent_[static_cast<std::size_t>(c) * 2 * D];
      for (int d = 0; d < D; ++d) {
        const int lo = static_cast<int>(e[d]), hi = static_cast<int>(-e[D + d]);
        base_[static_cast<std::size_t>(c)][static_cast<std::size_t>(d)] = lo;
        spread = std::max(spread, hi - lo);
        if (hi - lo > 1) {
          wide = true;
          if (bad < 0 && start[c] < start[c + 1]) bad = points[start[c]];
        }
      }
    }
    if (shared_) {  // (every process alike: the boxes' width is the unknowns' coupling width)
      wide = boxes->processes().any(wide);
      spread = static_cast<int>(boxes->processes().max(static_cast<long>(spread)));
    }
    if (wide) return bad;
    S = Sp + spread;
    K = 1;
    for (int d = 0; d < D; ++d) K *= S;
    node.resize(static_cast<std::size_t>(cells) * K);
    mean_div.assign(static_cast<std::size_t>(cells) * K, Vec<D>::Zero());
    volume.assign(static_cast<std::size_t>(cells), 0.0);
    local.resize(n * Kp);
    const bool axi = !inv_r.empty();
#pragma omp parallel for num_threads(threads) schedule(static)
    for (int c = 0; c < cells; ++c) {
      const std::array<int, D>& lo = base_[static_cast<std::size_t>(c)];
      std::size_t b0 = 0;
      for (int d = 0; d < D; ++d) b0 += static_cast<std::size_t>(lo[d]) * g.stride(d);
      for (int j = 0; j < K; ++j) {
        std::size_t o = 0;
        for (int d = 0, r = j; d < D; ++d, r /= S) o += static_cast<std::size_t>(r % S) * g.stride(d);
        node[static_cast<std::size_t>(c) * K + j] = static_cast<std::int64_t>(b0 + o);
      }
      double vc = 0.0;
      Vec<D>* b = &mean_div[static_cast<std::size_t>(c) * K];
      for (int q = start[c]; q < start[c + 1]; ++q) {
        const std::size_t p = static_cast<std::size_t>(points[q]);
        const auto ij = g.unflatten(static_cast<std::size_t>(st.node[p * Kp]));
        int shift = 0;
        for (int d = 0, pw = 1; d < D; ++d, pw *= S) shift += (ij[d] - lo[d]) * pw;
        const double V = point_volume[p];
        vc += V;
        for (int k = 0; k < Kp; ++k) {
          int j = shift;
          for (int d = 0, r = k, pw = 1; d < D; ++d, r /= Sp, pw *= S) j += (r % Sp) * pw;
          local[p * Kp + k] = j;
          Vec<D> div = st.dN[p * Kp + k];  // m^T B_pk
          if (axi) div[0] += st.N[p * Kp + k] * inv_r[p];
          b[j] += V * div;
        }
      }
      volume[static_cast<std::size_t>(c)] = vc;
    }
    sum_cells(volume.data(), 1);
    static_assert(sizeof(Vec<D>) == D * sizeof(double), "b_c summed as doubles");
    sum_cells(mean_div.empty() ? nullptr : mean_div[0].data(), K * D);
    for (int c = 0; c < cells; ++c)
      for (int j = 0; j < K; ++j)
        mean_div[static_cast<std::size_t>(c) * K + j] /= volume[static_cast<std::size_t>(c)];
    return -1;
  }

  int cells() const { return static_cast<int>(start.size()) - 1; }

  // Across processes: per-cell values (`per` a cell, in the cells' order) summed over the
  // processes whose points occupy the cell. Collective; nothing for one process.
  void sum_cells(double* v, int per) {
    if (!shared_) return;
    const std::size_t m = static_cast<std::size_t>(per);
    root_values_.resize(root_slot_.size() * m);
    leaf_values_.resize(leaf_slot_.size() * m);
    for (std::size_t k = 0; k < root_slot_.size(); ++k)
      std::copy_n(v + static_cast<std::size_t>(root_slot_[k]) * m, m, root_values_.data() + k * m);
    for (std::size_t k = 0; k < leaf_slot_.size(); ++k)
      std::copy_n(v + static_cast<std::size_t>(leaf_slot_[k]) * m, m, leaf_values_.data() + k * m);
    forest_.reduce(per, leaf_values_.data(), root_values_.data());
    forest_.broadcast(per, root_values_.data(), leaf_values_.data());
    for (std::size_t k = 0; k < root_slot_.size(); ++k)
      std::copy_n(root_values_.data() + k * m, m, v + static_cast<std::size_t>(root_slot_[k]) * m);
    for (std::size_t k = 0; k < leaf_slot_.size(); ++k)
      std::copy_n(leaf_values_.data() + k * m, m, v + static_cast<std::size_t>(leaf_slot_[k]) * m);
  }

 private:
  // Value `k` of `per` per cell: the least or greatest over the processes that occupy the cell.
  void combine_cells(double* v, int per, int k, StarForest::Combine how) {
    const std::size_t m = static_cast<std::size_t>(per), j = static_cast<std::size_t>(k);
    root_values_.resize(root_slot_.size());
    leaf_values_.resize(leaf_slot_.size());
    for (std::size_t q = 0; q < root_slot_.size(); ++q)
      root_values_[q] = v[static_cast<std::size_t>(root_slot_[q]) * m + j];
    for (std::size_t q = 0; q < leaf_slot_.size(); ++q)
      leaf_values_[q] = v[static_cast<std::size_t>(leaf_slot_[q]) * m + j];
    forest_.reduce(1, leaf_values_.data(), root_values_.data(), how);
    forest_.broadcast(1, root_values_.data(), leaf_values_.data());
    for (std::size_t q = 0; q < root_slot_.size(); ++q)
      v[static_cast<std::size_t>(root_slot_[q]) * m + j] = root_values_[q];
    for (std::size_t q = 0; q < leaf_slot_.size(); ++q)
      v[static_cast<std::size_t>(leaf_slot_[q]) * m + j] = leaf_values_[q];
  }
  // The star forest of the cells several processes occupy: over the boxes (which hold every
  // occupied cell's lower corner), how many processes occupy each and the lowest of them; a root
  // at that one, a leaf at each other, matched by the corner's node number.
  void share_cells(BoxExchange<D>& boxes) {
    const Processes& procs = boxes.processes();
    std::vector<double> count(corner_.size(), 1.0), lowest(corner_.size(), procs.rank());
    boxes.combine_slots(StarForest::Combine::Sum, slot_, count, 0.0);
    boxes.combine_slots(StarForest::Combine::Min, slot_, lowest, INFINITY);
    std::vector<long> roots, leaves;
    root_slot_.clear();
    leaf_slot_.clear();
    for (std::size_t c = 0; c < corner_.size(); ++c) {
      if (count[c] < 2.0) continue;
      const bool root = lowest[c] == static_cast<double>(procs.rank());
      (root ? roots : leaves).push_back(corner_[c]);
      (root ? root_slot_ : leaf_slot_).push_back(static_cast<std::int32_t>(c));
    }
    forest_.match_nodes(procs, static_cast<long>(occupied_.size() * 64), roots, leaves);
  }

  std::vector<std::int32_t> slot_, fill_;  // per grid cell; per cell (scratch)
  std::vector<std::uint64_t> occupied_;    // one bit per grid cell
  std::vector<double> extent_;             // per cell: lowest base, minus highest (per axis)
  std::vector<std::array<int, D>> base_;   // per cell: the box's low node
  // Across processes: each cell's lower corner (its grid cell), and the shared cells' forest with
  // the cells' slots of its roots and leaves (each ascending by corner).
  bool shared_ = false;
  std::vector<long> corner_;
  std::vector<std::int32_t> root_slot_, leaf_slot_;
  std::vector<double> root_values_, leaf_values_;
  StarForest forest_;
};

}  // namespace skred
