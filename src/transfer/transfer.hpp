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
#include "transfer/box_exchange.hpp"
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

  // The processes the points are split among (parallel/processes.hpp): set_box and reduce are
  // collective when they are several.
  void set_processes(const Processes& p) { processes_ = p; }
  const Processes& processes() const { return processes_; }

  // The box of nodes the current points can reach (set by every map from the points'
  // extent); every grid phase runs over it. Split among processes, each has its own points'
  // box, and every process learns the others' (box_exchange.hpp; collective).
  const NodeBox<D>& box() const { return box_; }
  void set_box(const Extent<D>& e) {
    box_ = reach_of(grid_, e);
    if (processes_.distributed()) exchange_.set(grid_, box_, processes_);
  }
  // The boxes of a distributed run, or null for one process alone.
  const BoxExchange<D>* exchange() const { return processes_.distributed() ? &exchange_ : nullptr; }
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
  // The threads' parts only, over the reach of `e`: one body's fields in a contact step, whose
  // sums over the processes wait for the step's box (every body's: sum_processes), so that each
  // process has every body's fields over its whole box.
  void reduce_threads(const Extent<D>& e, double* mass, Vec<D>* vec) {
    scatter_.reduce(grid_, reach_of(grid_, e), threads_, mass, vec);
  }
  void sum_processes(double* mass, Vec<D>* vec) {
    if (processes_.distributed()) sum_over_processes(mass, nullptr, vec);
  }
  // a and b (per-node scalars, zero where no point of this process reached) <- their sums over
  // the processes, over the box (the cell sums of the volumetric averaging).
  void sum_scalars(double* a, double* b) {
    if (processes_.distributed()) sum_over_processes(a, b, nullptr);
  }

  PointWeights<D>& weights() { return weights_; }

 private:
  // a, b (scalars) and vec (each if not null) summed over the processes where their boxes
  // overlap (box_exchange.hpp).
  void sum_over_processes(double* a, double* b, Vec<D>* vec) {
    const int per = (a ? 1 : 0) + (b ? 1 : 0) + (vec ? D : 0);
    exchange_.sum(
        per,
        [&](std::size_t i, double* at) {
          if (a) *at++ = a[i];
          if (b) *at++ = b[i];
          if (vec)
            for (int d = 0; d < D; ++d) at[d] = vec[i][d];
        },
        [&](std::size_t i, const double* at) {
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
  BoxExchange<D> exchange_;
};

}  // namespace skred
