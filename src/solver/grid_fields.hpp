// Nodal fields of the background grid, stored as structure-of-arrays, and the per-thread
// scatter buffers that make particle-to-grid transfers lock-free.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/huge_pages.hpp"
#include "core/types.hpp"

namespace skred {

template <int D> struct GridFields {
  GridArray<double> mass;        // m_i (Thesis eq. 2.53)
  GridArray<Vec<D>> momentum;    // m_i v_i (eq. 2.54), reused for the remap of USL/averaged
  // v_i^k after the velocity boundary conditions; once the grid update has used it, the
  // same storage holds v_i^{k+1} (for the PIC blend, and remapped from the updated points in
  // the USL and averaged schemes).
  GridArray<Vec<D>> velocity;
  // First the internal force f_i^int (eq. 2.51); the grid update turns it in place into the
  // acceleration (f_i + m_i g) / m_i and, after the boundary conditions,
  // (v_i^{k+1} - m_i v_i / m_i) / dt: the velocity change handed to the particles (FLIP
  // increment, eq. 2.56).
  GridArray<Vec<D>> accel;
  GridArray<Vec<D>> velocity_move; // (v_i^k + v_i^{k+1}) / 2: moves the particles (eq. 2.55)

  // n zero nodes (fresh pages: see GridArray). Call once, on empty fields.
  void resize(std::size_t n) {
    for (auto* f : {&momentum, &velocity, &accel, &velocity_move}) f->resize(n);
    mass.resize(n);
  }
  std::size_t size() const { return mass.size(); }
};

// What one thread scatters into. Thread 0 writes straight into the grid; threads 1..T-1
// write into their own buffers, which the reduction adds to the grid and clears again.
template <int D> struct ScatterBuffer {
  GridArray<double> mass;
  GridArray<Vec<D>> vec;  // momentum or force, depending on the pass
  // Lowest and highest block base written since the last reduction: the reduction covers
  // only this span (with particles in spatial order, a thread's own part of the grid).
  std::size_t lo = SIZE_MAX, hi = 0;
  void touched(std::size_t base_lo, std::size_t base_hi) {
    lo = std::min(lo, base_lo);
    hi = std::max(hi, base_hi);
  }
  void resize(std::size_t n) {  // n zero nodes; call once, on an empty buffer
    mass.resize(n);
    vec.resize(n);
  }
};

}  // namespace skred
