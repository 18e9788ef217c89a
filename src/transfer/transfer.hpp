// The transfer layer's state for one background grid: the geometry, the box of nodes the
// points reach, the per-thread scatter buffers and the points' stored weighting functions.
// The explicit solver owns one. (The implicit integrator, src/implicit, keeps its own weights
// per step; the "remap" of USL and the averaged scheme here is not Acosta's double mapping,
// which maps stresses to the grid and back.)
#pragma once
#include <algorithm>
#include <climits>
#include <cstddef>
#include <vector>

#include "core/grid.hpp"
#include "parallel/processes.hpp"
#include "shape/separable.hpp"
#include "transfer/node_box.hpp"
#include "transfer/point_weights.hpp"
#include "transfer/scatter.hpp"

namespace skred {

template <int D>
class Transfer {
 public:
  Transfer(const GridGeometry<D>& grid, int threads)
      : grid_(grid),
        strides_(grid),
        threads_(std::max(1, threads)),
        scatter_(grid.node_count(), std::max(1, threads)) {}

  const GridGeometry<D>& grid() const { return grid_; }
  const NodeStrides<D>& strides() const { return strides_; }
  int threads() const { return threads_; }

  // The processes the points are split among (parallel/processes.hpp): the box and every grid
  // sum are theirs together, so set_box and reduce are collective when they are several.
  void set_processes(const Processes& p) { processes_ = p; }
  const Processes& processes() const { return processes_; }

  // The box of nodes the current points can reach (set by every map from the points'
  // extent, every process's); every grid phase runs over it.
  const NodeBox<D>& box() const { return box_; }
  void set_box(Extent<D> e) {
    if (processes_.distributed()) {
      double ends[2 * D];
      for (int d = 0; d < D; ++d) {
        ends[d] = e.lo[d];
        ends[D + d] = -e.hi[d];
      }
      processes_.min(ends, 2 * D);
      for (int d = 0; d < D; ++d) {
        e.lo[d] = ends[d];
        e.hi[d] = -ends[D + d];
      }
    }
    box_ = reach_of(grid_, e);
  }
  template <class Fn>
  void for_box(Fn&& fn, int last_lo = 0, int last_hi = INT_MAX) const {
    skred::for_box(grid_, box_, threads_, fn, last_lo, last_hi);
  }

  ScatterBuffers<D>& scatter() { return scatter_; }
  // grid += the other threads' scatter buffers over the box (mass may be null); then, when the
  // points are split among processes, the sum of every process's grid over the box.
  void reduce(double* mass, Vec<D>* vec) {
    scatter_.reduce(grid_, box_, threads_, mass, vec);
    if (processes_.distributed()) sum_over_processes(mass, nullptr, vec);
  }
  // a and b (per-node scalars, zero where no point of this process reached) <- their sums over
  // the processes, over the box (the cell sums of the volumetric averaging).
  void sum_scalars(double* a, double* b) {
    if (processes_.distributed()) sum_over_processes(a, b, nullptr);
  }

  PointWeights<D>& weights() { return weights_; }

 private:
  // The box's nodes of a, b (scalars) and vec (each if not null), packed row by row, summed over
  // the processes in one message and unpacked (the buffer grows to the largest box, once).
  void sum_over_processes(double* a, double* b, Vec<D>* vec) {
    const long width = box_.hi[0] - box_.lo[0] + 1, rows = box_rows(box_);
    if (rows <= 0 || width <= 0) return;  // (the box is every process's: all return)
    const std::size_t per = (a ? 1 : 0) + (b ? 1 : 0) + (vec ? D : 0),
                      n = static_cast<std::size_t>(rows * width) * per;
    if (pack_.size() < n) pack_.resize(n);
    std::size_t stride[D];
    for (int d = 0; d < D; ++d) stride[d] = grid_.stride(d);
    const auto each = [&](auto&& fn) {
#pragma omp parallel for num_threads(threads_) schedule(static)
      for (long r = 0; r < rows; ++r) {
        const std::size_t row = box_row_start(box_, stride, r);
        double* at = pack_.data() + static_cast<std::size_t>(r * width) * per;
        for (long i = 0; i < width; ++i, at += per) fn(row + static_cast<std::size_t>(i), at);
      }
    };
    each([&](std::size_t i, double* at) {
      if (a) *at++ = a[i];
      if (b) *at++ = b[i];
      if (vec)
        for (int d = 0; d < D; ++d) at[d] = vec[i][d];
    });
    processes_.sum(pack_.data(), n);
    each([&](std::size_t i, const double* at) {
      if (a) a[i] = *at++;
      if (b) b[i] = *at++;
      if (vec)
        for (int d = 0; d < D; ++d) vec[i][d] = at[d];
    });
  }

  GridGeometry<D> grid_;
  NodeStrides<D> strides_;
  int threads_ = 1;
  NodeBox<D> box_;
  ScatterBuffers<D> scatter_;
  PointWeights<D> weights_;
  Processes processes_;
  std::vector<double> pack_;  // sum_over_processes
};

}  // namespace skred
