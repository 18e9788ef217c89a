// The points' weighting functions N_ip and gradients dN_ip/dx of one implicit step, evaluated
// once at the positions x^k the step starts from and kept through its Newton iterations
// (Acosta §2.1: the mesh deforms with the points during the step and is reset after it).
#pragma once
#include <omp.h>

#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/grid.hpp"
#include "core/particles.hpp"
#include "shape/stencil.hpp"

namespace skred {

template <int D>
struct PointStencils {
  int K = 0;                       // nodes per point (S^D of the kernel)
  std::vector<std::int64_t> node;  // flat grid index of entry p K + k
  std::vector<double> N;           // N_ip (Thesis eq. 2.46)
  std::vector<Vec<D>> dN;          // dN_ip / dx (eq. 2.47)

  std::size_t size() const { return K == 0 ? 0 : node.size() / static_cast<std::size_t>(K); }

  // Evaluates `kernel` at every point on `threads` threads; returns the first point whose
  // block of nodes leaves the grid, or -1.
  template <class Kernel>
  long build(const Kernel& kernel, const GridGeometry<D>& g, const Particles<D>& P, int threads) {
    using St = typename Kernel::StencilT;
    constexpr int S = St::width;
    K = St::size;
    const std::size_t n = P.size();
    node.resize(n * K);
    N.resize(n * K);
    dN.resize(n * K);
    const StencilOffsets<D, S> offsets(g);
    long bad = LONG_MAX;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(min : bad)
    for (std::size_t p = 0; p < n; ++p) {
      St st;
      if (!kernel(g, P.x[p], P.half0[p], P.F[p], st)) {
        bad = std::min(bad, static_cast<long>(p));
        for (int k = 0; k < K; ++k) {
          node[p * K + k] = 0;
          N[p * K + k] = 0.0;
          dN[p * K + k].setZero();
        }
        continue;
      }
      for (int k = 0; k < K; ++k) {
        node[p * K + k] = static_cast<std::int64_t>(st.base + offsets.off[static_cast<std::size_t>(k)]);
        N[p * K + k] = st.w[static_cast<std::size_t>(k)];
        dN[p * K + k] = st.grad[static_cast<std::size_t>(k)];
      }
    }
    return bad == LONG_MAX ? -1 : bad;
  }

  // Hands the weights of every sliver node (sliver[i] != 0: a sliver of a point's domain reaches
  // it) to the node one step nearer the point along each axis where it lies half a cell or more
  // away, and on until a node that is no sliver: a sliver's force is of the order of its width
  // e, its mass and stiffness of e^2, and as an unknown it would run off by 1 / e. The point's
  // weights still sum to one and its gradients to zero (a rigid motion strains nothing), as in
  // the cell aggregation of unfitted finite elements. A point all of whose nodes are slivers
  // keeps them.
  void aggregate_slivers(const GridGeometry<D>& g, const Particles<D>& P,
                         std::span<const std::uint8_t> sliver, int threads) {
    const std::size_t n = size();
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::size_t p = 0; p < n; ++p)
      for (int k = 0; k < K; ++k) {
        const std::size_t e = p * K + static_cast<std::size_t>(k);
        std::int64_t to = node[e];
        if (!sliver[static_cast<std::size_t>(to)] || N[e] == 0.0) continue;
        for (int hop = 0; hop < D && sliver[static_cast<std::size_t>(to)]; ++hop) {
          const Vec<D> d = g.node_position(static_cast<std::size_t>(to)) - P.x[p];
          for (int a = 0; a < D; ++a)
            if (std::abs(d[a]) >= 0.5 * g.h)
              to += (d[a] > 0.0 ? -1 : 1) * static_cast<std::int64_t>(g.stride(a));
        }
        int j = -1;
        for (int m = 0; m < K && j < 0; ++m)
          if (node[p * K + static_cast<std::size_t>(m)] == to && !sliver[static_cast<std::size_t>(to)]) j = m;
        if (j < 0) continue;
        N[p * K + static_cast<std::size_t>(j)] += N[e];
        dN[p * K + static_cast<std::size_t>(j)] += dN[e];
        N[e] = 0.0;
        dN[e].setZero();
      }
  }
};

}  // namespace skred
