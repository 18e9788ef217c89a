// Transparent huge pages for the big per-point and per-node arrays. A step streams a dozen
// arrays of 10^5-10^6 entries; with 4 KiB pages their TLB misses cost a few percent of a step
// (measured 3-4 % at 10^6 points). The kernel's default mode here is "madvise", so the arrays
// ask for 2 MiB pages before they are first touched.
#pragma once
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <utility>
#include <vector>

namespace skred {

// The whole pages of `page` bytes (a power of two) inside [p, p + bytes): [begin, end), empty
// when end <= begin.
inline std::pair<std::uintptr_t, std::uintptr_t> whole_pages(const void* p, std::size_t bytes,
                                                             std::uintptr_t page) {
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  return {(a + page - 1) & ~(page - 1), (a + bytes) & ~(page - 1)};
}

// Advises huge pages for the whole 2 MiB pages inside [p, p + bytes). A hint only: failure
// (or a kernel without THP) changes nothing but speed.
inline void advise_huge_pages(const void* p, std::size_t bytes) {
  [[maybe_unused]] const auto [begin, end] = whole_pages(p, bytes, std::uintptr_t{1} << 21);
#ifdef MADV_HUGEPAGE
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#endif
}

// Gives the whole pages inside [p, p + bytes) of private anonymous memory (a GridArray) back
// to the kernel; they read as zero when next touched (MADV_DONTNEED).
inline void release_pages(void* p, std::size_t bytes) {
  const auto [begin, end] = whole_pages(p, bytes, static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE)));
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED);
}

// Bytes of the pages touching [p, p + bytes) that are resident in memory (mincore; for tests).
inline std::size_t resident_bytes(const void* p, std::size_t bytes) {
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto begin = reinterpret_cast<std::uintptr_t>(p) & ~(page - 1);
  const auto end = reinterpret_cast<std::uintptr_t>(p) + bytes;
  std::vector<unsigned char> in((end - begin + page - 1) / page);
  if (mincore(reinterpret_cast<void*>(begin), end - begin, in.data()) != 0) return 0;
  return static_cast<std::size_t>(
             std::count_if(in.begin(), in.end(), [](unsigned char c) { return c & 1; })) *
         page;
}

// Reserves room for n entries and advises huge pages for it, before any entry is touched.
template <class T, class A>
void reserve_huge(std::vector<T, A>& v, std::size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

// Allocator for the grid arrays: memory comes zeroed and untouched, and resize() does not write
// it, so pages of nodes no point ever reaches are never touched and cost no resident memory. A
// large array is mapped from the kernel directly (fresh zero pages): calloc would hand out a free
// chunk of the heap when it has one, and zero it by writing every page (after a distributed
// run's set-up has freed the others' points, each process's whole grid would then be resident).
template <class T>
struct ZeroPageAllocator {
  using value_type = T;
  static constexpr std::size_t kMappedBytes = std::size_t{1} << 20;  // from here on: mmap
  ZeroPageAllocator() = default;
  template <class U>
  ZeroPageAllocator(const ZeroPageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes >= kMappedBytes) {
      void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      if (p == MAP_FAILED) throw std::bad_alloc();
      return static_cast<T*>(p);
    }
    void* p = std::calloc(n, sizeof(T));
    if (!p) throw std::bad_alloc();
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) >= kMappedBytes)
      munmap(p, n * sizeof(T));
    else
      std::free(p);
  }
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
