// The part of the grid a step works on: the box of nodes the points' stencils can reach, the
// points' extent that sets it, and the OpenMP reductions the transfers use.
#pragma once
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/grid.hpp"
#include "core/inline.hpp"
#include "core/types.hpp"

namespace skred {

// Widest stencil of the kernels (B-spline and GIMP quadrature: four nodes per axis).
inline constexpr int kMaxStencil = 4;

// A box of grid nodes, per axis the first and last index (empty when hi < lo).
template <int D>
struct NodeBox {
  std::array<int, D> lo{}, hi{};
  NodeBox() {
    for (int d = 0; d < D; ++d) hi[d] = -1;
  }
  bool empty() const {
    for (int d = 0; d < D; ++d)
      if (hi[d] < lo[d]) return true;
    return false;
  }
  long count() const {
    long n = 1;
    for (int d = 0; d < D; ++d) n *= std::max(0, hi[d] - lo[d] + 1);
    return n;
  }
};

// The extent of the points, per axis the lowest and highest coordinate. Kept in registers in
// the hot loops and merged across threads with reduction(merge : extent).
template <int D>
struct Extent {
  Vec<D> lo = Vec<D>::Constant(INFINITY), hi = Vec<D>::Constant(-INFINITY);
  SKRED_INLINE void add(const Vec<D>& x) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  void merge(const Extent& o) {
    lo = lo.cwiseMin(o.lo);
    hi = hi.cwiseMax(o.hi);
  }
};
#pragma omp declare reduction(merge : Extent <2>, Extent <3> : omp_out.merge(omp_in))

// Sum of vectors across OpenMP threads: reduction(vsum : v).
#pragma omp declare reduction(vsum : Vec <2> : omp_out += omp_in) initializer(omp_priv = Vec <2>::Zero())
#pragma omp declare reduction(vsum : Vec <3> : omp_out += omp_in) initializer(omp_priv = Vec <3>::Zero())

// Lowest and highest stencil base (flat node index) a thread scattered to.
struct BaseSpan {
  std::size_t lo = SIZE_MAX, hi = 0;
  SKRED_INLINE void add(std::size_t base) {
    lo = std::min(lo, base);
    hi = std::max(hi, base);
  }
  void merge(const BaseSpan& o) {
    lo = std::min(lo, o.lo);
    hi = std::max(hi, o.hi);
  }
  bool empty() const { return lo > hi; }
};

// The nodes the stencils of points within `e` can reach: per axis from the lowest to the
// highest point, widened by the widest stencil plus one (so that points moving less than a
// cell within a step stay inside). Outside it the grid fields are zero and never read.
template <int D>
NodeBox<D> reach_of(const GridGeometry<D>& g, const Extent<D>& e) {
  NodeBox<D> box;
  for (int d = 0; d < D; ++d) {
    if (!(e.lo[d] <= e.hi[d])) return NodeBox<D>{};  // no points
    const double inv_h = 1.0 / g.h, reach = kMaxStencil + 1;
    const double a = std::floor((e.lo[d] - g.origin[d]) * inv_h) + GridGeometry<D>::pad - reach;
    const double b = std::floor((e.hi[d] - g.origin[d]) * inv_h) + GridGeometry<D>::pad + reach;
    box.lo[d] = static_cast<int>(std::clamp(a, 0.0, g.nodes(d) - 1.0));
    box.hi[d] = static_cast<int>(std::clamp(b, 0.0, g.nodes(d) - 1.0));
  }
  return box;
}

// The rows of a box: its lines of nodes along axis 0, numbered with axis 1 fastest.
template <int D>
long box_rows(const NodeBox<D>& b) {
  if (b.hi[0] < b.lo[0]) return 0;
  long rows = 1;
  for (int d = 1; d < D; ++d) rows *= std::max(0, b.hi[d] - b.lo[d] + 1);
  return rows;
}
// The flat index of the first node of row r of box b (stride: the grid's, per axis).
template <int D>
std::size_t box_row_start(const NodeBox<D>& b, const std::size_t (&stride)[D], long r) {
  std::size_t row = static_cast<std::size_t>(b.lo[0]);
  for (int d = 1; d < D; ++d) {
    const long n = b.hi[d] - b.lo[d] + 1;
    row += static_cast<std::size_t>(b.lo[d] + r % n) * stride[d];
    r /= n;
  }
  return row;
}

// fn(i) for every node i of `box` (or of its part with last-axis index in [last_lo,
// last_hi]), in parallel over its rows.
template <int D, class Fn>
void for_box(const GridGeometry<D>& g, NodeBox<D> b, int threads, Fn&& fn, int last_lo = 0,
             int last_hi = INT_MAX) {
  b.lo[D - 1] = std::max(b.lo[D - 1], last_lo);
  b.hi[D - 1] = std::min(b.hi[D - 1], last_hi);
  const long width = b.hi[0] - b.lo[0] + 1;
  const long rows = box_rows(b);
  std::size_t stride[D];
  for (int d = 0; d < D; ++d) stride[d] = g.stride(d);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (long r = 0; r < rows; ++r) {
    const std::size_t row = box_row_start(b, stride, r);
    for (long i = 0; i < width; ++i) fn(row + static_cast<std::size_t>(i));
  }
}

}  // namespace skred
