// Lock-free particle-to-grid scatters: thread 0 writes straight into the grid arrays, every
// other thread into its own buffer, which reduce() adds to the grid and clears again.
#pragma once
#include <algorithm>
#include <climits>
#include <cstddef>
#include <cstdint>
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
  // resident, and reduce() hands back to the kernel the pages its points have left (release),
  // so a buffer's memory follows the layers of nodes its thread's points span now, not the
  // grid nor the region they swept.
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
      release(b, first, last, layer);
    }
  }

  // Bytes of thread t's buffer (t >= 1) that are resident in memory (mincore), for tests.
  std::size_t resident_bytes(int t) const {
    const Buffer& b = buffers_[static_cast<std::size_t>(t - 1)];
    return skred::resident_bytes(b.mass.data(), b.mass.size() * sizeof(double)) +
           skred::resident_bytes(b.vec.data(), b.vec.size() * sizeof(Vec<D>));
  }

 private:
  struct Buffer {
    GridArray<double> mass;
    GridArray<Vec<D>> vec;
    BaseSpan span;                        // stencil bases written since the last reduction
    int held_lo = INT_MAX, held_hi = -1;  // layers (last-axis indices) that may hold resident pages
  };
  std::vector<Buffer> buffers_;

  // Layers further than this many bytes of the vector array from the ones just reduced are
  // handed back: the buffer holds at most that much beyond its points' span, and a slowly
  // moving span costs a system call only every so often.
  static constexpr std::size_t kReleaseSlack = std::size_t{1} << 20;

  // After b was reduced over the layers [first, last] of `layer` nodes (and so is zero everywhere), gives the
  // pages of the layers it held outside them back to the kernel (MADV_DONTNEED: private
  // anonymous pages read as zero again when next touched) once they exceed kReleaseSlack.
  void release(Buffer& b, int first, int last, std::size_t layer) {
    last = std::min(last, static_cast<int>(b.vec.size() / layer) - 1);
    b.held_lo = std::min(b.held_lo, first);
    b.held_hi = std::max(b.held_hi, last);
    const auto bytes = [&](int lo, int hi) {
      return hi < lo ? 0 : static_cast<std::size_t>(hi - lo + 1) * layer * sizeof(Vec<D>);
    };
    if (bytes(b.held_lo, first - 1) + bytes(last + 1, b.held_hi) < kReleaseSlack) return;
    for (const auto& [lo, hi] : {std::pair{b.held_lo, first - 1}, std::pair{last + 1, b.held_hi}}) {
      if (hi < lo) continue;
      const std::size_t n0 = static_cast<std::size_t>(lo) * layer,
                        n1 = static_cast<std::size_t>(hi + 1) * layer;
      release_pages(b.mass.data() + n0, (n1 - n0) * sizeof(double));
      release_pages(b.vec.data() + n0, (n1 - n0) * sizeof(Vec<D>));
    }
    b.held_lo = first;
    b.held_hi = last;
  }
};

}  // namespace skred
