// A row of S grid nodes of a Vec<D> array is S*D contiguous doubles (a "lane" per node and
// component). RowLanes<L> holds such a row in 4-wide vectors plus a scalar tail, so the
// separable transfers (separable.hpp) read, weight and write a whole row with a few vector
// operations instead of S small Vec<D> operations (3D rows of 3 doubles per node map badly
// onto vector registers otherwise). GCC/Clang vector extensions: no intrinsics, any x86-64
// or other target.
#pragma once
#include <cstring>

#include "core/inline.hpp"

namespace skred {

template <int L>
struct RowLanes {
  using V4 = double __attribute__((vector_size(32)));
  static constexpr int N = L / 4, R = L % 4;
  V4 v[N > 0 ? N : 1];
  double t[R > 0 ? R : 1];

  SKRED_INLINE static RowLanes zero() {
    RowLanes r;
    for (int i = 0; i < N; ++i) r.v[i] = V4{0.0, 0.0, 0.0, 0.0};
    for (int i = 0; i < R; ++i) r.t[i] = 0.0;
    return r;
  }
  SKRED_INLINE static RowLanes load(const double* p) {
    RowLanes r;
    for (int i = 0; i < N; ++i) std::memcpy(&r.v[i], p + 4 * i, sizeof(V4));
    for (int i = 0; i < R; ++i) r.t[i] = p[4 * N + i];
    return r;
  }
  SKRED_INLINE void store(double* p) const {
    for (int i = 0; i < N; ++i) std::memcpy(p + 4 * i, &v[i], sizeof(V4));
    for (int i = 0; i < R; ++i) p[4 * N + i] = t[i];
  }
  // this += k x
  SKRED_INLINE void add(double k, const RowLanes& x) {
    for (int i = 0; i < N; ++i) v[i] += k * x.v[i];
    for (int i = 0; i < R; ++i) t[i] += k * x.t[i];
  }
  SKRED_INLINE double operator[](int l) const { return l < 4 * N ? v[l / 4][l % 4] : t[l - 4 * N]; }
};

}  // namespace skred
