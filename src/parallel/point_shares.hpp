// Each process's share of the points of a distributed run (processes.hpp): a contiguous run of
// them in their order, points [n r / N, n (r + 1) / N) of process r of N, so that the points a
// process holds lie together when they are sorted by cell. Every process builds all the points
// and keeps its share (the set-up is not yet distributed).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/particles.hpp"
#include "parallel/processes.hpp"

namespace skred {

template <int D>
void keep_share(Particles<D>& P, const Processes& procs) {
  if (!procs.distributed()) return;
  const std::size_t n = P.size(), r = static_cast<std::size_t>(procs.rank()),
                    k = static_cast<std::size_t>(procs.size());
  std::vector<std::uint8_t> keep(n, 0);
  for (std::size_t p = n * r / k; p < n * (r + 1) / k; ++p) keep[p] = 1;
  P.erase(keep);
}

}  // namespace skred
