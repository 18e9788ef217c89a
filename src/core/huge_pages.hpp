// Transparent huge pages for the big per-point and per-node arrays. A step streams a dozen
// arrays of 10^5-10^6 entries; with 4 KiB pages their TLB misses cost a few percent of a step
// (measured 3-4 % at 10^6 points). The kernel's default mode here is "madvise", so the arrays
// ask for 2 MiB pages before they are first touched.
#pragma once
#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <utility>
#include <vector>

namespace skred {

// Advises huge pages for the whole 2 MiB pages inside [p, p + bytes). A hint only: failure
// (or a kernel without THP) changes nothing but speed.
inline void advise_huge_pages(const void* p, std::size_t bytes) {
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  const auto begin = (reinterpret_cast<std::uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(kHuge - 1);
#ifdef MADV_HUGEPAGE
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#endif
}

// Reserves room for n entries and advises huge pages for it, before any entry is touched.
template <class T, class A>
void reserve_huge(std::vector<T, A>& v, std::size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

// Allocator for the grid arrays: memory comes zeroed from calloc (for large arrays fresh
// pages from the kernel) and resize() does not write it, so pages of nodes no point ever
// reaches are never touched and cost no resident memory.
template <class T>
struct ZeroPageAllocator {
  using value_type = T;
  ZeroPageAllocator() = default;
  template <class U>
  ZeroPageAllocator(const ZeroPageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    void* p = std::calloc(n, sizeof(T));
    if (!p) throw std::bad_alloc();
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) noexcept { std::free(p); }
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }  // zero page
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
  template <class U>
  bool operator==(const ZeroPageAllocator<U>&) const noexcept {
    return true;
  }
};

// A grid array: zero-initialised without touching its pages (see ZeroPageAllocator).
template <class T>
using GridArray = std::vector<T, ZeroPageAllocator<T>>;

}  // namespace skred
