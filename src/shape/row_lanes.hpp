// A row of S grid nodes of a Vec<D> array is S*D contiguous doubles (a "lane" per node and
// component). RowLanes<L> holds such a row in 8- and 4-wide vectors plus a scalar tail, so the
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
  using V8 = double __attribute__((vector_size(64)));
  using V4 = double __attribute__((vector_size(32)));
  // 8-wide vectors first (one AVX-512 register, or two 4-wide ones where there is none), then
  // at most one 4-wide vector, then scalars.
  static constexpr int N8 = L / 8, N4 = (L % 8) / 4, R = L % 4, O4 = 8 * N8, OR = O4 + 4 * N4;
  V8 w[N8 > 0 ? N8 : 1];
  V4 v[N4 > 0 ? N4 : 1];
  double t[R > 0 ? R : 1];

  SKRED_INLINE static RowLanes zero() {
    RowLanes r;
    for (int i = 0; i < N8; ++i) r.w[i] = V8{};
    for (int i = 0; i < N4; ++i) r.v[i] = V4{};
    for (int i = 0; i < R; ++i) r.t[i] = 0.0;
    return r;
  }
  SKRED_INLINE static RowLanes load(const double* p) {
    RowLanes r;
    for (int i = 0; i < N8; ++i) std::memcpy(&r.w[i], p + 8 * i, sizeof(V8));
    for (int i = 0; i < N4; ++i) std::memcpy(&r.v[i], p + O4 + 4 * i, sizeof(V4));
    for (int i = 0; i < R; ++i) r.t[i] = p[OR + i];
    return r;
  }
  SKRED_INLINE void store(double* p) const {
    for (int i = 0; i < N8; ++i) std::memcpy(p + 8 * i, &w[i], sizeof(V8));
    for (int i = 0; i < N4; ++i) std::memcpy(p + O4 + 4 * i, &v[i], sizeof(V4));
    for (int i = 0; i < R; ++i) p[OR + i] = t[i];
  }
  // this += k x
  SKRED_INLINE void add(double k, const RowLanes& x) {
    for (int i = 0; i < N8; ++i) w[i] += k * x.w[i];
    for (int i = 0; i < N4; ++i) v[i] += k * x.v[i];
    for (int i = 0; i < R; ++i) t[i] += k * x.t[i];
  }
  SKRED_INLINE double operator[](int l) const {
    return l < O4 ? w[l / 8][l % 8] : l < OR ? v[(l - O4) / 4][l % 4] : t[l - OR];
  }
};

}  // namespace skred
