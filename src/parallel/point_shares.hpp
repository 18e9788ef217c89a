// Each process's share of the points of a distributed run (processes.hpp): a contiguous run of
// them in their order, points [n r / N, n (r + 1) / N) of process r of N, so that the points a
// process holds lie together when they are sorted by cell. Every process builds all the points
// and keeps its share (the set-up is not yet distributed), in turns (in_turns).
#pragma once
#include <cstddef>
#include <cstdint>
#include <exception>
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
  P.shrink();  // (the memory of the others' points goes back)
}

// Runs make() (which builds all the points and keeps this process's share) in every process, the
// processes of one machine in turn, so that its memory holds one whole set of points at a time
// and not one per process. When make() throws in one, every process throws: that one its error,
// the others `others` (the set-up is the same in each, so they would meet the same error).
template <class Make, class Others>
void in_turns(const Processes& procs, Make&& make, Others&& others) {
  std::exception_ptr failed;
  bool any_failed = false;
  for (int turn = 0; turn < procs.local_size() && !any_failed; ++turn) {
    if (turn == procs.local_rank()) try {
        make();
      } catch (...) {
        failed = std::current_exception();
      }
    any_failed = procs.any(failed != nullptr);  // (also the barrier between the turns)
  }
  if (failed) std::rethrow_exception(failed);
  if (any_failed) others();
}

}  // namespace skred
