// Look-ahead of the part of a point's weighting functions that does not depend on its
// position: GIMP's half-lengths l_p = l_p^0 det(F)^(1/ndim) (Thesis eq. 3.23), a root and
// divisions that are the longest chain of a point's weights. A loop that moves points and
// maps them at their new positions, without changing F, forms them for the next 8 points at
// once, in the lanes of vectors (GimpKernel::sizes), when it reaches a point it has none for.
// In 2D (a square root) it does not pay: there, and for kernels without such a part, the
// point's initial half-lengths are passed on and shape() forms the rest as before.
#pragma once
#include <algorithm>
#include <type_traits>

#include "core/grid.hpp"
#include "core/inline.hpp"
#include "core/types.hpp"

namespace skred {

template <class K>
concept SizedKernel = requires {
  typename K::Size;
};

template <int D, class K>
constexpr bool kSizeAhead = D == 3 && SizedKernel<K>;

template <class K, bool>
struct SizeOf {
  struct type {};
};
template <class K>
struct SizeOf<K, true> {
  using type = typename K::Size;
};

template <int D, class K>
struct SizeAhead {
  // What map_point takes as the point's size: K::Size, or half0 itself. From the points' det F
  // if `det_f` is given (the stress phase of the step wrote it: docs/method.md, "det F from
  // the stress phase"), else from F.
  SKRED_INLINE auto take(const K& kernel, const GridGeometry<D>& g, const Vec<D>* __restrict half0,
                         const Mat<D>* __restrict F, const double* __restrict det_f, long p, long n) {
    if constexpr (kSizeAhead<D, K>) {
      static_assert(K::kSizeLanes <= kBlock);
      if (p < first_ || p >= first_ + count_) {
        first_ = p;
        count_ = static_cast<int>(std::min<long>(K::kSizeLanes, n - p));
        if (det_f) {
          kernel.sizes_at(g, half0 + p, det_f + p, count_, block_);
        } else {
          kernel.sizes(g, half0 + p, F + p, count_, block_);
          // and asks for the cache lines of the F of the block after next (docs/method.md, "Prefetches")
          for (long q = p + 2 * K::kSizeLanes; q < std::min(n, p + 3 * K::kSizeLanes); ++q)
            __builtin_prefetch(F + q);
        }
      }
      return block_[p - first_];
    } else {
      return half0[p];
    }
  }

 private:
  static constexpr int kBlock = 8;
  typename SizeOf<K, kSizeAhead<D, K>>::type block_[kBlock]{};  // points [first_, first_ + count_)
  long first_ = -1;
  int count_ = 0;
};

}  // namespace skred
