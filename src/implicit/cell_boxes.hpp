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
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/grid.hpp"
#include "core/particles.hpp"
#include "implicit/point_stencils.hpp"
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
  long build(const PointStencils<D>& st, int Sp, const GridGeometry<D>& g, const Particles<D>& P,
             const std::vector<double>& point_volume, const std::vector<double>& inv_r, int threads) {
    const std::size_t n = P.size();
    const int Kp = st.K;
    // Group the points by cell (counting sort over the grid's cells, in point order).
    slot_.assign(g.node_count(), -1);
    cell.resize(n);
    int cells = 0;
    for (std::size_t p = 0; p < n; ++p) {
      std::int32_t& s = slot_[VolumetricAveraging<D>::cell_of(g, P.x[p])];
      if (s < 0) s = cells++;
      cell[p] = s;
    }
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
    base_.resize(static_cast<std::size_t>(cells));
    int spread = 0;
    long bad = -1;
    for (int c = 0; c < cells; ++c) {
      std::array<int, D> lo, hi;
      lo.fill(1 << 30);
      hi.fill(-1);
      for (int q = start[c]; q < start[c + 1]; ++q) {
        const auto ij =
            g.unflatten(static_cast<std::size_t>(st.node[static_cast<std::size_t>(points[q]) * Kp]));
        for (int d = 0; d < D; ++d) lo[d] = std::min(lo[d], ij[d]), hi[d] = std::max(hi[d], ij[d]);
      }
      for (int d = 0; d < D; ++d) {
        spread = std::max(spread, hi[d] - lo[d]);
        if (hi[d] - lo[d] > 1 && bad < 0) bad = points[start[c]];
      }
      base_[static_cast<std::size_t>(c)] = lo;
    }
    if (bad >= 0) return bad;
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
      for (int j = 0; j < K; ++j) b[j] /= vc;
    }
    return -1;
  }

  int cells() const { return static_cast<int>(start.size()) - 1; }

 private:
  std::vector<std::int32_t> slot_, fill_;  // per grid cell; per cell (scratch)
  std::vector<std::array<int, D>> base_;   // per cell: the box's low node
};

}  // namespace skred
