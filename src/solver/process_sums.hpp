// Sums of the points' own quantities over the processes a run is split among
// (parallel/processes.hpp): the energies a phase books, the momentum of a move, the particle
// totals. One message per call; nothing at all for one process.
#pragma once
#include <array>
#include <cstddef>

#include "core/types.hpp"
#include "parallel/processes.hpp"

namespace skred {

namespace process_sums {
template <class T>
struct Width;  // doubles per value
template <>
struct Width<double> {
  static constexpr std::size_t value = 1;
};
template <>
struct Width<Vec<2>> {
  static constexpr std::size_t value = 2;
};
template <>
struct Width<Vec<3>> {
  static constexpr std::size_t value = 3;
};
inline void put(double* buf, std::size_t& at, const double& v) { buf[at++] = v; }
template <int D>
void put(double* buf, std::size_t& at, const Vec<D>& v) {
  for (int d = 0; d < D; ++d) buf[at++] = v[d];
}
inline void take(const double* buf, std::size_t& at, double& v) { v = buf[at++]; }
template <int D>
void take(const double* buf, std::size_t& at, Vec<D>& v) {
  for (int d = 0; d < D; ++d) v[d] = buf[at++];
}
}  // namespace process_sums

// v... (doubles and vectors) <- their sums over the processes.
template <class... T>
void sum_over_processes(const Processes& processes, T&... v) {
  if (!processes.distributed()) return;
  std::array<double, (0 + ... + process_sums::Width<T>::value)> buf{};
  std::size_t at = 0;
  (process_sums::put(buf.data(), at, v), ...);
  processes.sum(buf.data(), buf.size());
  at = 0;
  (process_sums::take(buf.data(), at, v), ...);
}

}  // namespace skred
