// Cell-averaged volumetric strain, the MPM form of the B-bar method against volumetric locking
// (Hughes 1980; for MPM e.g. Mast et al. 2012, Coombs et al. 2018): a point's strain increment
// keeps its own deviatoric part and takes the volume-weighted mean volumetric part of the points
// in its cell, d_eps_p + (div_c - div_p)/d I, and the internal force pairs with it by taking the
// cell's volume-weighted mean pressure m_c in place of the point's own, sigma_p + (m_c - m_p) I,
// so that the stress power of the points equals the work of the nodal forces (per cell,
// sum V_p m_p (div_c - div_p) = sum V_p (m_c - m_p) div_p). m = tr(sigma)/d over the d in-plane
// axes: in plane strain the in-plane trace is the volumetric strain; in axisymmetric geometry
// the hoop axis is the third (d = 3, div = tr grad v + v_r / r).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/grid.hpp"
#include "core/types.hpp"

namespace skred {

template <int D>
struct VolumetricAveraging {
  // Per cell, indexed by the flat index of its low node: sums of V div, V, V m, V.
  std::vector<double> div_sum, volume_sum, mean_sum, mean_volume_sum;
  // Per point: its cell, its own velocity gradient (the stress update's, kept from the pass that
  // sums the divergences rather than gathered twice), its divergence tr grad v, mean in-plane
  // stress m_p and the volume its sums weigh it by.
  std::vector<std::uint32_t> cell;
  std::vector<Mat<D>> grad;
  std::vector<double> div, mean, volume;
  // Axisymmetric geometry (2D): the volumetric strain and the mean stress take the hoop axis too
  // (axes = 3), and each point's hoop rate v_r / r is kept beside its grad v.
  int axes = D;
  std::vector<double> hoop_rate;
  // The cell sums, made in parallel and the same for any thread count (ExplicitSolver::cell_sums):
  // per chunk of kSumChunk points (a fixed size, not a thread's share) its runs of consecutive
  // points in one cell, each summed in point order (the points are sorted by cell, so a cell's
  // points are mostly one run); then add_runs adds the runs to their cells chunk by chunk on one
  // thread. (Summing the runs inside the stress update's own loop instead was slower: measured
  // 0.272 against 0.233 s of the bench's stress phase on two threads.)
  struct Run {
    std::uint32_t cell;
    double value, volume;  // sums of V value and V over the run
  };
  static constexpr long kSumChunk = 1024;
  std::vector<Run> runs;        // chunk c's runs from runs[c * kSumChunk] on
  std::vector<long> run_count;  // per chunk

  // Sized for the grid and the points (allocates only when either grew).
  void resize(const GridGeometry<D>& g, std::size_t points) {
    const std::size_t nodes = g.node_count();
    for (auto* a : {&div_sum, &volume_sum, &mean_sum, &mean_volume_sum})
      if (a->size() != nodes) a->assign(nodes, 0.0);
    if (axes != D) hoop_rate.resize(points);
    if (cell.size() != points) {
      cell.resize(points), grad.resize(points), div.resize(points), mean.resize(points),
          volume.resize(points);
      runs.resize(points), run_count.resize(static_cast<std::size_t>(chunk_count(points)));
    }
  }

  static long chunk_count(std::size_t points) {
    return (static_cast<long>(points) + kSumChunk - 1) / kSumChunk;
  }
  // Chunk c's runs of the selected points among the first n (cell and volume as held here):
  // V value and V summed over each run of consecutive points in one cell, in point order.
  template <class Sel>
  void sum_chunk(long c, long n, Sel sel, const double* value) {
    Run* out = runs.data() + c * kSumChunk;
    long last = -1;
    for (long p = c * kSumChunk, p1 = std::min(n, p + kSumChunk); p < p1; ++p) {
      if (!sel(p)) continue;
      if (last >= 0 && out[last].cell == cell[p]) {
        out[last].value += volume[p] * value[p];
        out[last].volume += volume[p];
      } else {
        out[++last] = Run{cell[p], volume[p] * value[p], volume[p]};
      }
    }
    run_count[c] = last + 1;
  }
  // Each cell a run of the chunks touches gets the sum of its runs' V value in sum and of their V
  // in weight, added in chunk order.
  void add_runs(long chunks, double* sum, double* weight) const {
    for (long k = 0; k < chunks; ++k)
      for (const Run *r = runs.data() + k * kSumChunk, *end = r + run_count[k]; r < end; ++r)
        sum[r->cell] = weight[r->cell] = 0.0;
    for (long k = 0; k < chunks; ++k)
      for (const Run *r = runs.data() + k * kSumChunk, *end = r + run_count[k]; r < end; ++r) {
        sum[r->cell] += r->value;
        weight[r->cell] += r->volume;
      }
  }

  // The cell holding x (points on the grid's walls belong to the cell inside).
  static std::uint32_t cell_of(const GridGeometry<D>& g, const Vec<D>& x) {
    std::size_t c = 0;
    for (int d = 0; d < D; ++d) {
      int i = static_cast<int>(std::floor((x[d] - g.origin[d]) / g.h));
      i = i < 0 ? 0 : (i >= g.cells[d] ? g.cells[d] - 1 : i);
      c += static_cast<std::size_t>(i + GridGeometry<D>::pad) * g.stride(d);
    }
    return static_cast<std::uint32_t>(c);
  }

  // The correction to point p's grad v: (div_c - div_p)/d on the diagonal (d = axes).
  double correction(std::size_t p) const {
    const std::uint32_t c = cell[p];
    return (div_sum[c] / volume_sum[c] - div[p]) / axes;
  }
  // The correction to point p's stress in the force: m_c - m_p on the diagonal.
  double pressure_correction(std::size_t p) const {
    const std::uint32_t c = cell[p];
    return mean_sum[c] / mean_volume_sum[c] - mean[p];
  }
};

}  // namespace skred
