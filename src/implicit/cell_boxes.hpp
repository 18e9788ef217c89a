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
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/grid.hpp"
#include "core/particles.hpp"
#include "implicit/point_stencils.hpp"
#include "parallel/processes.hpp"
#include "solver/volumetric_averaging.hpp"

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
  // Across processes (issue 55) the cells are those any process's points occupy, numbered in
  // the grid's order alike in all of them (a cell without points here has none in `points`);
  // a box starts at the lowest stencil base of all its cell's points, and V_c and b_c are every
  // process's sums. A process returns its own failing point or -1, and all of them return early
  // alike (the caller agrees on the point).
  long build(const PointStencils<D>& st, int Sp, const GridGeometry<D>& g, const Particles<D>& P,
             const std::vector<double>& point_volume, const std::vector<double>& inv_r, int threads,
             const Processes& procs = {}) {
    const std::size_t n = P.size();
    const int Kp = st.K;
    // The occupied cells (one bit per grid cell, by its lower node), numbered in the grid's order.
    const std::size_t grid_cells = g.node_count();
    occupied_.assign((grid_cells + 63) / 64, 0);
    cell.resize(n);
    for (std::size_t p = 0; p < n; ++p) {
      const std::uint32_t c = VolumetricAveraging<D>::cell_of(g, P.x[p]);
      cell[p] = static_cast<std::int32_t>(c);
      occupied_[c / 64] |= std::uint64_t{1} << (c % 64);
    }
    procs.bit_or(occupied_.data(), occupied_.size());
    slot_.assign(grid_cells, -1);
    int cells = 0;
    for (std::size_t w = 0; w < occupied_.size(); ++w)
      for (std::uint64_t bits = occupied_[w]; bits; bits &= bits - 1)
        slot_[64 * w + static_cast<std::size_t>(std::countr_zero(bits))] = cells++;
    for (std::size_t p = 0; p < n; ++p) cell[p] = slot_[static_cast<std::size_t>(cell[p])];
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
    procs.min(extent_.data(), extent_.size());
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
    procs.sum(volume.data(), volume.size());
    static_assert(sizeof(Vec<D>) == D * sizeof(double), "b_c summed as doubles");
    procs.sum(mean_div.empty() ? nullptr : mean_div[0].data(), mean_div.size() * D);
    for (int c = 0; c < cells; ++c)
      for (int j = 0; j < K; ++j)
        mean_div[static_cast<std::size_t>(c) * K + j] /= volume[static_cast<std::size_t>(c)];
    return -1;
  }

  int cells() const { return static_cast<int>(start.size()) - 1; }

 private:
  std::vector<std::int32_t> slot_, fill_;  // per grid cell; per cell (scratch)
  std::vector<std::uint64_t> occupied_;    // one bit per grid cell
  std::vector<double> extent_;             // per cell: lowest base, minus highest (per axis)
  std::vector<std::array<int, D>> base_;   // per cell: the box's low node
};

}  // namespace skred
