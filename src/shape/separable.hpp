// Separable kernels (linear, GIMP, B-spline) are tensor products of 1D weighting functions
// (Thesis eq. 3.15). The solver evaluates a point's 1D functions once per time step, keeps
// them in packed form through the phases of the step, and expands the tensor product on the
// fly while it scatters to or gathers from the S^D block of nodes.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "core/inline.hpp"
#include "shape/row_lanes.hpp"
#include "shape/stencil.hpp"

namespace skred {

// Per axis the S 1D weighting functions and their derivatives, and the flat index of the
// block's first node.
template <int D, int S>
struct Separable {
  std::size_t base = 0;
  double w[D][S];
  double g[D][S];
};

// Storage form of Separable between the phases of a step. The 1D functions of every kernel
// are a partition of unity (sum w = 1, sum g = 0 on each axis), so the entry `Skip`, chosen
// per kernel as one that never comes near zero, is not stored but recovered from the others.
template <int D, int S, int Skip>
struct PackedSeparable {
  std::int64_t base = 0;
  double w[D][S - 1];
  double g[D][S - 1];

  SKRED_INLINE void pack(const Separable<D, S>& s) {
    base = static_cast<std::int64_t>(s.base);
    for (int d = 0; d < D; ++d)
      for (int a = 0, j = 0; a < S; ++a)
        if (a != Skip) {
          w[d][j] = s.w[d][a];
          g[d][j++] = s.g[d][a];
        }
  }
  SKRED_INLINE void unpack(Separable<D, S>& s) const {
    s.base = static_cast<std::size_t>(base);
    for (int d = 0; d < D; ++d) {
      double sw = 0.0, sg = 0.0;
      for (int a = 0, j = 0; a < S; ++a)
        if (a != Skip) {
          s.w[d][a] = w[d][j];
          s.g[d][a] = g[d][j];
          sw += w[d][j];
          sg += g[d][j++];
        }
      s.w[d][Skip] = 1.0 - sw;
      s.g[d][Skip] = -sg;
    }
  }
};

// What the separable kernels share, given their shape() (CRTP): the stored form with the
// entry Skip omitted, and the full stencil for tests and post-processing.
template <class Kernel, int D, int S, int Skip>
struct SeparableKernel {
  using StencilT = Stencil<D, S>;
  using Shape = Separable<D, S>;
  using Packed = PackedSeparable<D, S, Skip>;

  static void store(Packed& p, const Shape& sh, const Mat<D>& /*F*/) { p.pack(sh); }
  SKRED_INLINE static void load(const Packed& p, const GridGeometry<D>& /*g*/, const Vec<D>& /*x*/,
                                const Vec<D>& /*half0*/, Shape& sh) {
    p.unpack(sh);
  }
  bool operator()(const GridGeometry<D>& g, const Vec<D>& x, const Vec<D>& half0, const Mat<D>& F,
                  StencilT& st) const;
};

// Flat-index strides of the grid axes, for walking a block of nodes.
template <int D>
struct NodeStrides {
  std::size_t s[D];
  explicit NodeStrides(const GridGeometry<D>& g) {
    for (int d = 0; d < D; ++d) s[d] = g.stride(d);
  }
};

// Calls fn(node, N_ip, grad N_ip) for every node of the point's block (eq. 3.15).
template <int D, int S, class Fn>
SKRED_INLINE void for_each_node(const Separable<D, S>& sh, const NodeStrides<D>& st, Fn&& fn) {
  if constexpr (D == 2) {
    for (int b = 0; b < S; ++b) {
      const std::size_t row = sh.base + b * st.s[1];
      const double wy = sh.w[1][b], gy = sh.g[1][b];
      for (int a = 0; a < S; ++a) fn(row + a, sh.w[0][a] * wy, Vec<2>(sh.g[0][a] * wy, sh.w[0][a] * gy));
    }
  } else {
    static_assert(D == 3, "skred supports 2D and 3D");
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b) {
        const std::size_t row = sh.base + b * st.s[1] + c * st.s[2];
        const double wyz = sh.w[1][b] * sh.w[2][c];
        const double gy = sh.g[1][b] * sh.w[2][c], gz = sh.w[1][b] * sh.g[2][c];
        for (int a = 0; a < S; ++a)
          fn(row + a, sh.w[0][a] * wyz, Vec<3>(sh.g[0][a] * wyz, sh.w[0][a] * gy, sh.w[0][a] * gz));
      }
  }
}

// The same walk over a general (non-separable) stencil.
template <int D, int S, class Fn>
SKRED_INLINE void for_each_node(const Stencil<D, S>& sh, const NodeStrides<D>& st, Fn&& fn) {
  for (int k = 0; k < Stencil<D, S>::size; ++k) {
    std::size_t off = 0;
    int r = k;
    for (int d = 0; d < D; ++d) {
      off += static_cast<std::size_t>(r % S) * st.s[d];
      r /= S;
    }
    fn(sh.base + off, sh.w[k], sh.grad[k]);
  }
}

// The transfers of the time step, written once for both stencil forms. On a separable
// stencil they are sum-factorised: the sums over a row of nodes are formed first and then
// weighted by the row's function, so a node costs a few multiply-adds; in 3D a whole row is
// one short vector of lanes (row_lanes.hpp).

// 3D rows in lanes (row_lanes.hpp): the row of S nodes at (b, c) of a point's block as
// 3 S contiguous doubles, and the rows' (y, z) weights N_y N_z, dN_y N_z, N_y dN_z.
namespace lanes3 {
template <int S>
using Row = RowLanes<3 * S>;
template <int S, class T>
SKRED_INLINE T* row(T* f, const Separable<3, S>& sh, const NodeStrides<3>& st, int b, int c) {
  return f + 3 * (sh.base + b * st.s[1] + c * st.s[2]);
}

// Lane (a, i) = w[a] x_i: a 1D function's values times a 3-vector, as the row scatters add it.
// For three nodes (GIMP) built in registers by permutes: written lane by lane through memory,
// the row's wide load waits on the narrow stores (a store-forwarding stall per row vector).
template <int S>
SKRED_INLINE Row<S> outer(const double (&w)[S], double x0, double x1, double x2) {
  Row<S> r;
  if constexpr (S == 3) {
    using V4 = RowLanes<9>::V4;
    const V4 wv = {w[0], w[1], w[2], 0.0}, xv = {x0, x1, x2, 0.0};
    r.w[0] = __builtin_shufflevector(wv, wv, 0, 0, 0, 1, 1, 1, 2, 2) *
             __builtin_shufflevector(xv, xv, 0, 1, 2, 0, 1, 2, 0, 1);
    r.t[0] = w[2] * x2;
  } else {
    double l[3 * S];
    for (int a = 0; a < S; ++a) {
      l[3 * a] = w[a] * x0;
      l[3 * a + 1] = w[a] * x1;
      l[3 * a + 2] = w[a] * x2;
    }
    r = Row<S>::load(l);
  }
  return r;
}

// out_i = sum_a w[a] r(a, i): a row sum weighted by a 1D function (the last step of a gather).
template <int S>
SKRED_INLINE Vec<3> contract(const Row<S>& r, const double (&w)[S]) {
  if constexpr (S == 3) {
    using V4 = RowLanes<9>::V4;
    const V4 wv = {w[0], w[1], w[2], 0.0};
    const auto prod = r.w[0] * __builtin_shufflevector(wv, wv, 0, 0, 0, 1, 1, 1, 2, 2);
    const decltype(prod) zero{};  // lanes (0, i) + (1, i) + (2, i); (2, 2) is the tail
    const V4 sum = __builtin_shufflevector(prod, prod, 0, 1, 2, 3) +
                   __builtin_shufflevector(prod, prod, 3, 4, 5, 6) +
                   __builtin_shufflevector(prod, zero, 6, 7, 8, 8);
    return Vec<3>(sum[0], sum[1], sum[2] + w[2] * r.t[0]);
  } else {
    Vec<3> out = Vec<3>::Zero();
    for (int a = 0; a < S; ++a)
      for (int i = 0; i < 3; ++i) out[i] += w[a] * r[3 * a + i];
    return out;
  }
}
}  // namespace lanes3

// sum_i N_ip f_i (eq. 2.56, Post eq. 31).
template <int D, int S, class T>
SKRED_INLINE T gather(const Separable<D, S>& sh, const NodeStrides<D>& st, const T* __restrict f) {
  T out = T::Zero();
  if constexpr (D == 2) {
    for (int b = 0; b < S; ++b) {
      const T* r = f + sh.base + b * st.s[1];
      T row = sh.w[0][0] * r[0];
      for (int a = 1; a < S; ++a) row += sh.w[0][a] * r[a];
      out += sh.w[1][b] * row;
    }
  } else if constexpr (std::is_same_v<T, Vec<3>>) {
    static_assert(sizeof(Vec<3>) == 3 * sizeof(double), "rows of Vec<3> must be contiguous doubles");
    const double* fd = reinterpret_cast<const double*>(f);
    auto acc = lanes3::Row<S>::zero();
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b)
        acc.add(sh.w[1][b] * sh.w[2][c], lanes3::Row<S>::load(lanes3::row(fd, sh, st, b, c)));
    out = lanes3::contract(acc, sh.w[0]);
  } else {
    for (int c = 0; c < S; ++c) {
      T plane = T::Zero();
      for (int b = 0; b < S; ++b) {
        const T* r = f + sh.base + b * st.s[1] + c * st.s[2];
        T row = sh.w[0][0] * r[0];
        for (int a = 1; a < S; ++a) row += sh.w[0][a] * r[a];
        plane += sh.w[1][b] * row;
      }
      out += sh.w[2][c] * plane;
    }
  }
  return out;
}

// sum_i N_ip f_i over the nodes of the block on the given layers only: node (a, b[, c]) counts
// when bit a of layers[0], bit b of layers[1] or bit c of layers[2] is set (the nodes on a wall,
// where a field that is zero elsewhere lives: a third of the block or less next to one wall).
template <int D, int S>
SKRED_INLINE Vec<D> gather_layers(const Separable<D, S>& sh, const NodeStrides<D>& st,
                                  const Vec<D>* __restrict f,
                                  const std::type_identity_t<std::array<unsigned, D>>& layers) {
  Vec<D> out = Vec<D>::Zero();
  if constexpr (D == 2) {
    for (int b = 0; b < S; ++b) {
      const Vec<D>* r = f + sh.base + b * st.s[1];
      const bool row = (layers[1] >> b) & 1u;
      for (int a = 0; a < S; ++a)
        if (row || ((layers[0] >> a) & 1u)) out += (sh.w[0][a] * sh.w[1][b]) * r[a];
    }
  } else {
    // whole rows (along x) on a y or z wall layer in lanes, as gather does; single nodes on an x one
    const double* fd = reinterpret_cast<const double*>(f);
    auto acc = lanes3::Row<S>::zero();
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b) {
        const double k = sh.w[1][b] * sh.w[2][c];
        if (((layers[1] >> b) & 1u) || ((layers[2] >> c) & 1u)) {
          acc.add(k, lanes3::Row<S>::load(lanes3::row(fd, sh, st, b, c)));
        } else if (layers[0] != 0u) {
          const Vec<D>* r = f + sh.base + b * st.s[1] + c * st.s[2];
          for (int a = 0; a < S; ++a)
            if ((layers[0] >> a) & 1u) out += (sh.w[0][a] * k) * r[a];
        }
      }
    out += lanes3::contract(acc, sh.w[0]);
  }
  return out;
}

// The gathers sum_i N_ip f_i and sum_i N_ip g_i of two nodal fields in one walk (the point
// update reads the acceleration and the moving velocity with the same weights).
template <int D, int S>
SKRED_INLINE void gather_pair(const Separable<D, S>& sh, const NodeStrides<D>& st, const Vec<D>* __restrict f,
                              const Vec<D>* __restrict g, Vec<D>& out_f, Vec<D>& out_g) {
  if constexpr (D == 2) {
    out_f = gather(sh, st, f);
    out_g = gather(sh, st, g);
  } else {
    const double* fd = reinterpret_cast<const double*>(f);
    const double* gd = reinterpret_cast<const double*>(g);
    auto af = lanes3::Row<S>::zero(), ag = af;
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b) {
        const double k = sh.w[1][b] * sh.w[2][c];
        af.add(k, lanes3::Row<S>::load(lanes3::row(fd, sh, st, b, c)));
        ag.add(k, lanes3::Row<S>::load(lanes3::row(gd, sh, st, b, c)));
      }
    out_f = lanes3::contract(af, sh.w[0]);
    out_g = lanes3::contract(ag, sh.w[0]);
  }
}

// sum_i v_i (x) grad N_ip: the velocity gradient of eq. 2.20.
template <int D, int S>
SKRED_INLINE Mat<D> gather_gradient(const Separable<D, S>& sh, const NodeStrides<D>& st,
                                    const Vec<D>* __restrict v) {
  Mat<D> out = Mat<D>::Zero();
  if constexpr (D == 2) {
    for (int b = 0; b < S; ++b) {
      const Vec<2>* r = v + sh.base + b * st.s[1];
      Vec<2> rg = sh.g[0][0] * r[0], rw = sh.w[0][0] * r[0];
      for (int a = 1; a < S; ++a) {
        rg += sh.g[0][a] * r[a];
        rw += sh.w[0][a] * r[a];
      }
      out.col(0) += sh.w[1][b] * rg;
      out.col(1) += sh.g[1][b] * rw;
    }
  } else {
    // Rows summed with the weights N_y N_z, dN_y N_z and N_y dN_z; the x functions last.
    const double* vd = reinterpret_cast<const double*>(v);
    auto a0 = lanes3::Row<S>::zero(), a1 = a0, a2 = a0;
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b) {
        const auto r = lanes3::Row<S>::load(lanes3::row(vd, sh, st, b, c));
        a0.add(sh.w[1][b] * sh.w[2][c], r);
        a1.add(sh.g[1][b] * sh.w[2][c], r);
        a2.add(sh.w[1][b] * sh.g[2][c], r);
      }
    out.col(0) = lanes3::contract(a0, sh.g[0]);
    out.col(1) = lanes3::contract(a1, sh.w[0]);
    out.col(2) = lanes3::contract(a2, sh.w[0]);
  }
  return out;
}

// f_i += N_ip x (mass and momentum maps, eq. 2.53-2.54).
template <int D, int S, class T>
SKRED_INLINE void scatter(const Separable<D, S>& sh, const NodeStrides<D>& st, const T& x, T* __restrict f) {
  if constexpr (D == 2) {
    for (int b = 0; b < S; ++b) {
      T* r = f + sh.base + b * st.s[1];
      const T xb = sh.w[1][b] * x;
      for (int a = 0; a < S; ++a) r[a] += sh.w[0][a] * xb;
    }
  } else if constexpr (std::is_same_v<T, Vec<3>>) {
    double* fd = reinterpret_cast<double*>(f);
    const auto px = lanes3::outer(sh.w[0], x[0], x[1], x[2]);  // N_x(a) x_i in lane (a, i)
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b) {
        double* r = lanes3::row(fd, sh, st, b, c);
        auto row = lanes3::Row<S>::load(r);
        row.add(sh.w[1][b] * sh.w[2][c], px);
        row.store(r);
      }
  } else {
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b) {
        T* r = f + sh.base + b * st.s[1] + c * st.s[2];
        const T xb = (sh.w[1][b] * sh.w[2][c]) * x;
        for (int a = 0; a < S; ++a) r[a] += sh.w[0][a] * xb;
      }
  }
}
template <int D, int S>
SKRED_INLINE void scatter(const Separable<D, S>& sh, const NodeStrides<D>& st, double x,
                          double* __restrict f) {
  if constexpr (D == 3 && S == 3) {
    // A row of three nodes' masses as a 2-wide vector and a scalar: two loads, two
    // multiply-adds and two stores where node by node takes three of each.
    using V2 = double __attribute__((vector_size(16)));
    const V2 w01 = {sh.w[0][0], sh.w[0][1]};  // (the products in scatter's order: N_ip, then m_p)
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b) {
        double* r = f + sh.base + b * st.s[1] + c * st.s[2];
        const double k = sh.w[1][b] * sh.w[2][c];
        V2 r01;
        std::memcpy(&r01, r, sizeof(V2));
        r01 += (w01 * k) * x;
        std::memcpy(r, &r01, sizeof(V2));
        r[2] += (sh.w[0][2] * k) * x;
      }
  } else {
    for_each_node(sh, st, [&](std::size_t i, double w, const Vec<D>&) { f[i] += w * x; });
  }
}

// f_i += A grad N_ip (internal force with A = -sigma_p V_p, eq. 2.51).
template <int D, int S>
SKRED_INLINE void scatter_gradient(const Separable<D, S>& sh, const NodeStrides<D>& st, const Mat<D>& A,
                                   Vec<D>* __restrict f) {
  if constexpr (D == 2) {
    for (int b = 0; b < S; ++b) {
      Vec<2>* r = f + sh.base + b * st.s[1];
      const Vec<2> c0 = sh.w[1][b] * A.col(0), c1 = sh.g[1][b] * A.col(1);
      for (int a = 0; a < S; ++a) r[a] += sh.g[0][a] * c0 + sh.w[0][a] * c1;
    }
  } else {
    // Lane (a, i) holds dN_x(a) A_i0, N_x(a) A_i1, N_x(a) A_i2; a row adds them weighted by
    // its N_y N_z, dN_y N_z, N_y dN_z.
    double* fd = reinterpret_cast<double*>(f);
    const auto p0 = lanes3::outer(sh.g[0], A(0, 0), A(1, 0), A(2, 0));
    const auto p1 = lanes3::outer(sh.w[0], A(0, 1), A(1, 1), A(2, 1));
    const auto p2 = lanes3::outer(sh.w[0], A(0, 2), A(1, 2), A(2, 2));
    for (int c = 0; c < S; ++c)
      for (int b = 0; b < S; ++b) {
        double* r = lanes3::row(fd, sh, st, b, c);
        auto row = lanes3::Row<S>::load(r);
        row.add(sh.w[1][b] * sh.w[2][c], p0);
        row.add(sh.g[1][b] * sh.w[2][c], p1);
        row.add(sh.w[1][b] * sh.g[2][c], p2);
        row.store(r);
      }
  }
}

// The same transfers on a general stencil.
template <int D, int S, class T>
SKRED_INLINE T gather(const Stencil<D, S>& sh, const NodeStrides<D>& st, const T* __restrict f) {
  T out = T::Zero();
  for_each_node(sh, st, [&](std::size_t i, double w, const Vec<D>&) { out += w * f[i]; });
  return out;
}
template <int D, int S>
SKRED_INLINE Mat<D> gather_gradient(const Stencil<D, S>& sh, const NodeStrides<D>& st,
                                    const Vec<D>* __restrict v) {
  Mat<D> out = Mat<D>::Zero();
  for_each_node(sh, st,
                [&](std::size_t i, double, const Vec<D>& g) { out.noalias() += v[i] * g.transpose(); });
  return out;
}
template <int D, int S, class T>
SKRED_INLINE void scatter(const Stencil<D, S>& sh, const NodeStrides<D>& st, const T& x, T* __restrict f) {
  for_each_node(sh, st, [&](std::size_t i, double w, const Vec<D>&) { f[i] += w * x; });
}
template <int D, int S>
SKRED_INLINE void scatter(const Stencil<D, S>& sh, const NodeStrides<D>& st, double x, double* __restrict f) {
  for_each_node(sh, st, [&](std::size_t i, double w, const Vec<D>&) { f[i] += w * x; });
}
template <int D, int S>
SKRED_INLINE void scatter_gradient(const Stencil<D, S>& sh, const NodeStrides<D>& st, const Mat<D>& A,
                                   Vec<D>* __restrict f) {
  for_each_node(sh, st, [&](std::size_t i, double, const Vec<D>& g) { f[i].noalias() += A * g; });
}

template <int D, int S>
SKRED_INLINE Vec<D> gather_layers(const Stencil<D, S>& sh, const NodeStrides<D>& st,
                                  const Vec<D>* __restrict f,
                                  const std::type_identity_t<std::array<unsigned, D>>&) {
  return gather(sh, st, f);  // (a general stencil: every node)
}
template <int D, int S>
SKRED_INLINE void gather_pair(const Stencil<D, S>& sh, const NodeStrides<D>& st, const Vec<D>* __restrict f,
                              const Vec<D>* __restrict g, Vec<D>& out_f, Vec<D>& out_g) {
  out_f = gather(sh, st, f);
  out_g = gather(sh, st, g);
}

// A separable kernel's full stencil (for tests and post-processing).
template <int D, int S>
inline void expand(const Separable<D, S>& sh, Stencil<D, S>& st) {
  st.base = sh.base;
  tensor_product<D, S>(sh.w, sh.g, st);
}

template <class Kernel, int D, int S, int Skip>
bool SeparableKernel<Kernel, D, S, Skip>::operator()(const GridGeometry<D>& g, const Vec<D>& x,
                                                     const Vec<D>& half0, const Mat<D>& F,
                                                     StencilT& st) const {
  Shape sh;
  if (!static_cast<const Kernel&>(*this).shape(g, x, half0, F, sh)) return false;
  expand(sh, st);
  return true;
}

}  // namespace skred
