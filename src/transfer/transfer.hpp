// The transfer layer's state for one background grid: the geometry, the box of nodes the
// points reach, the per-thread scatter buffers and the points' stored weighting functions.
// The explicit solver owns one. (The implicit integrator, src/implicit, keeps its own weights
// per step; the "remap" of USL and the averaged scheme here is not Acosta's double mapping,
// which maps stresses to the grid and back.)
#pragma once
#include <algorithm>
#include <climits>

#include "core/grid.hpp"
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

  // The box of nodes the current points can reach (set by every map from the points'
  // extent); every grid phase runs over it.
  const NodeBox<D>& box() const { return box_; }
  void set_box(const Extent<D>& e) { box_ = reach_of(grid_, e); }
  template <class Fn>
  void for_box(Fn&& fn, int last_lo = 0, int last_hi = INT_MAX) const {
    skred::for_box(grid_, box_, threads_, fn, last_lo, last_hi);
  }

  ScatterBuffers<D>& scatter() { return scatter_; }
  // grid += the other threads' scatter buffers over the box (mass may be null).
  void reduce(double* mass, Vec<D>* vec) { scatter_.reduce(grid_, box_, threads_, mass, vec); }

  PointWeights<D>& weights() { return weights_; }

 private:
  GridGeometry<D> grid_;
  NodeStrides<D> strides_;
  int threads_ = 1;
  NodeBox<D> box_;
  ScatterBuffers<D> scatter_;
  PointWeights<D> weights_;
};

}  // namespace skred
