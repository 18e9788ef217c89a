// Lock-free particle-to-grid scatters: thread 0 writes straight into the grid arrays, every
// other thread into its own buffer, which reduce() adds to the grid and clears again.
#pragma once
#include <cstddef>
#include <vector>

#include "core/grid.hpp"
#include "core/huge_pages.hpp"
#include "core/types.hpp"
#include "transfer/node_box.hpp"

namespace skred {

template <int D>
class ScatterBuffers {
 public:
  ScatterBuffers() = default;
  // One buffer per thread beyond the first, each of `nodes` zero nodes. The buffers come
  // from untouched zero pages (GridArray): only the pages a thread's points reach become
  // resident, so their memory follows the region the points cover, not the grid.
  ScatterBuffers(std::size_t nodes, int threads) : buffers_(threads > 1 ? threads - 1 : 0) {
    for (auto& b : buffers_) {
      b.mass.resize(nodes);
      b.vec.resize(nodes);
    }
  }

  // Where thread t scatters a scalar (mass) or vector (momentum, force) field.
  double* mass_target(int t, double* grid) { return t == 0 ? grid : buffers_[t - 1].mass.data(); }
  Vec<D>* vec_target(int t, Vec<D>* grid) { return t == 0 ? grid : buffers_[t - 1].vec.data(); }
  // Records the stencil bases thread t wrote to since the last reduction.
  void touched(int t, const BaseSpan& s) {
    if (t > 0) buffers_[t - 1].span.merge(s);
  }

  // grid += buffers over `box` (only the part of it the buffers' blocks reached), buffers
  // cleared. `mass` may be null when only a vector field was scattered.
  void reduce(const GridGeometry<D>& g, const NodeBox<D>& box, int threads, double* mass, Vec<D>* vec) {
    const std::size_t layer = g.stride(D - 1);  // nodes per index of the last axis
    for (auto& b : buffers_) {
      if (b.span.empty()) continue;
      const int first = static_cast<int>(b.span.lo / layer);
      const int last = static_cast<int>(b.span.hi / layer) + kMaxStencil - 1;
      double* __restrict bm = b.mass.data();
      Vec<D>* __restrict bv = b.vec.data();
      for_box(
          g, box, threads,
          [&](std::size_t i) {
            if (mass) {
              mass[i] += bm[i];
              bm[i] = 0.0;
            }
            vec[i] += bv[i];
            bv[i].setZero();
          },
          first, last);
      b.span = BaseSpan{};
    }
  }

 private:
  struct Buffer {
    GridArray<double> mass;
    GridArray<Vec<D>> vec;
    BaseSpan span;  // stencil bases written since the last reduction
  };
  std::vector<Buffer> buffers_;
};

}  // namespace skred
