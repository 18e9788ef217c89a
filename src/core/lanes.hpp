// Eight doubles in the lanes of one vector (GCC/Clang vector extensions), for the parts of the
// step that run eight points side by side, one per lane (solver/stress_lanes_3d.hpp). Where
// AVX-512 is there, one intrinsic gives the lanes' square roots; elsewhere a loop does.
#pragma once
#include <cmath>
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

// A 3-vector per lane.
struct V3 {
  V8 x, y, z;
};
SKRED_INLINE V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
SKRED_INLINE V8 dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
SKRED_INLINE V3 scaled(const V3& a, V8 k) { return {a.x * k, a.y * k, a.z * k}; }
SKRED_INLINE V3 divided(const V3& a, V8 k) { return {a.x / k, a.y / k, a.z / k}; }
SKRED_INLINE V3 select(M8 m, const V3& a, const V3& b) {
  return {m ? a.x : b.x, m ? a.y : b.y, m ? a.z : b.z};
}

}  // namespace skred::lanes
