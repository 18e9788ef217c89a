// Eight doubles in the lanes of one vector (GCC/Clang vector extensions), for the parts of the
// step that run eight points side by side, one per lane (solver/stress_lanes_3d.hpp). Where
// AVX-512 is there, one intrinsic gives the lanes' square roots; elsewhere a loop does.
#pragma once
#include <cmath>
#include <cstring>
#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "core/inline.hpp"

namespace skred::lanes {

inline constexpr int kLanes = 8;
using V8 = double __attribute__((vector_size(64)));
using M8 = long long __attribute__((vector_size(64)));  // a comparison's lanes: all ones or zero

SKRED_INLINE V8 splat(double x) { return V8{x, x, x, x, x, x, x, x}; }
SKRED_INLINE V8 sqrt8(V8 x) {
#if defined(__AVX512F__)
  const __m512d v = static_cast<__m512d>(x);
  return static_cast<V8>(_mm512_mask_sqrt_pd(v, 0xff, v));  // (all lanes; GCC 12 warns on _mm512_sqrt_pd)
#else
  V8 r;
  for (int l = 0; l < kLanes; ++l) r[l] = std::sqrt(x[l]);
  return r;
#endif
}
SKRED_INLINE V8 abs8(V8 x) { return x < 0.0 ? -x : x; }
SKRED_INLINE V8 max8(V8 a, V8 b) { return a > b ? a : b; }
// One bit per lane: bit l set where lane l of the comparison holds.
SKRED_INLINE unsigned bits(M8 m) {
  unsigned b = 0;
  for (int l = 0; l < kLanes; ++l) b |= (m[l] != 0 ? 1u : 0u) << l;
  return b;
}
// The lanes of a bit mask as a comparison's lanes.
SKRED_INLINE M8 lanes_of(unsigned b) {
  M8 m;
  for (int l = 0; l < kLanes; ++l) m[l] = ((b >> l) & 1u) ? -1 : 0;
  return m;
}

// Component c of eight consecutive records of `Stride` doubles, one record per lane.
template <int Stride>
SKRED_INLINE V8 load(const double* __restrict base, int c) {
  V8 v;  // (AVX-512's gather instruction was no faster)
  for (int l = 0; l < kLanes; ++l) v[l] = base[l * Stride + c];
  return v;
}
// The eight records' first eight components in the lanes of eight vectors, or back: an 8 x 8
// transpose in three rounds of two-vector shuffles.
SKRED_INLINE void transpose8(V8 (&r)[8]) {
  V8 t[8];
  for (int i = 0; i < 8; i += 2) {
    t[i] = __builtin_shufflevector(r[i], r[i + 1], 0, 8, 2, 10, 4, 12, 6, 14);
    t[i + 1] = __builtin_shufflevector(r[i], r[i + 1], 1, 9, 3, 11, 5, 13, 7, 15);
  }
  for (int i = 0; i < 8; i += 4)
    for (int j = 0; j < 2; ++j) {
      r[i + j] = __builtin_shufflevector(t[i + j], t[i + j + 2], 0, 1, 8, 9, 4, 5, 12, 13);
      r[i + j + 2] = __builtin_shufflevector(t[i + j], t[i + j + 2], 2, 3, 10, 11, 6, 7, 14, 15);
    }
  for (int j = 0; j < 4; ++j) {
    t[j] = __builtin_shufflevector(r[j], r[j + 4], 0, 1, 2, 3, 8, 9, 10, 11);
    t[j + 4] = __builtin_shufflevector(r[j], r[j + 4], 4, 5, 6, 7, 12, 13, 14, 15);
  }
  for (int j = 0; j < 8; ++j) r[j] = t[j];
}
// The nine components of eight consecutive 3 x 3 matrices (column-major, 9 doubles each) as
// nine vectors: whole records through the transpose, the ninth component lane by lane.
SKRED_INLINE void load_mat(const double* __restrict base, V8 (&c)[9]) {
  V8 r[8];
  for (int l = 0; l < kLanes; ++l) std::memcpy(&r[l], base + 9 * l, sizeof(V8));
  transpose8(r);
  for (int k = 0; k < 8; ++k) c[k] = r[k];
  c[8] = load<9>(base, 8);
}
// ... and back (every lane: a lane left out must be given its old value).
SKRED_INLINE void store_mat(double* __restrict base, const V8 (&c)[9]) {
  V8 r[8];
  for (int k = 0; k < 8; ++k) r[k] = c[k];
  transpose8(r);
  for (int l = 0; l < kLanes; ++l) {
    std::memcpy(base + 9 * l, &r[l], sizeof(V8));
    base[9 * l + 8] = c[8][l];
  }
}
// A 3-vector per lane.
struct V3 {
  V8 x, y, z;
};
SKRED_INLINE V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
SKRED_INLINE V8 dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
SKRED_INLINE V3 divided(const V3& a, V8 k) { return {a.x / k, a.y / k, a.z / k}; }
SKRED_INLINE V3 select(M8 m, const V3& a, const V3& b) {
  return {m ? a.x : b.x, m ? a.y : b.y, m ? a.z : b.z};
}

}  // namespace skred::lanes
