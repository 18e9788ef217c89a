// Each process's share of the points of a distributed run (processes.hpp): a contiguous run of
// them in their order, points [n r / N, n (r + 1) / N) of process r of N, so that the points a
// process holds lie together when they are sorted by cell. Every process builds all the points
// and keeps its share (the set-up is not yet distributed), in turns (in_turns). Splitting adds
// points where the material stretches, so shares drift apart: even_out_shares hands points on
// to even them out again.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <type_traits>
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

// The imbalance of the shares: the most points a process holds over the mean (1: even).
template <int D>
double share_imbalance(const Particles<D>& P, const Processes& procs) {
  const long own = static_cast<long>(P.size()), all = procs.sum_of(own), most = procs.max(own);
  return all > 0 ? static_cast<double>(most) * procs.size() / static_cast<double>(all) : 1.0;
}

// Evens the shares out: the points keep their order over all processes (rank order, as the
// shares of keep_share), and process r then holds the r-th of N equal runs of it (the points it
// gives and takes move in one MPI_Alltoallv per field). An optional field that some process
// holds is held by all afterwards (its initial value where it was not). Every process calls it.
template <int D>
void even_out_shares(Particles<D>& P, const Processes& procs) {
  if (!procs.distributed()) return;
  const std::size_t k = static_cast<std::size_t>(procs.size());
  std::vector<double> own{static_cast<double>(P.size())}, counts(k);
  procs.gather(own.data(), 1, counts.data(), k);
  std::vector<long> first(k + 1, 0);  // the shares' first points now, over all processes
  for (std::size_t q = 0; q < k; ++q) first[q + 1] = first[q] + static_cast<long>(counts[q]);
  const long total = first[k];
  const auto target = [&](std::size_t q) { return static_cast<long>(total * static_cast<double>(q) / k); };
  const std::size_t r = static_cast<std::size_t>(procs.rank());
  const auto overlap = [](long a0, long a1, long b0, long b1) {
    return std::max(0L, std::min(a1, b1) - std::max(a0, b0));
  };
  std::vector<long> give(k), take(k);  // points to and from each process
  for (std::size_t q = 0; q < k; ++q) {
    give[q] = overlap(first[r], first[r + 1], target(q), target(q + 1));
    take[q] = overlap(first[q], first[q + 1], target(r), target(r + 1));
  }
  const long mine = target(r + 1) - target(r);
  const std::size_t held = P.size();
  std::vector<double> present;  // per field: held here (1) or not
  P.for_each_field(
      [&](const auto& f, const auto& a) { present.push_back(f.optional && a.empty() ? 0.0 : 1.0); });
  procs.max(present.data(), present.size());
  std::size_t at = 0;
  std::vector<long> give_bytes(k), take_bytes(k);
  P.for_each_field([&](const auto& f, auto& a) {
    if (present[at++] == 0.0) return;
    using T = typename std::decay_t<decltype(f)>::value_type;
    if (a.empty()) a.assign(held, f.initial());  // (an optional field another process holds)
    for (std::size_t q = 0; q < k; ++q) {
      give_bytes[q] = give[q] * static_cast<long>(sizeof(T));
      take_bytes[q] = take[q] * static_cast<long>(sizeof(T));
    }
    std::decay_t<decltype(a)> b(static_cast<std::size_t>(mine));
    procs.exchange(a.data(), give_bytes, b.data(), take_bytes);
    a.swap(b);
  });
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
