// Each process's share of the points of a distributed run (processes.hpp). At the set-up every
// process builds all the points and keeps a contiguous run of them in their order (keep_share:
// points [n r / N, n (r + 1) / N) of process r of N), in turns (in_turns); the run then keeps them
// in slabs of the grid (repartition_in_slabs), so that each process's points, and the box of
// nodes they reach, lie together, and points move to a neighbour as they cross a slab's cut.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <type_traits>
#include <vector>

#include "core/grid.hpp"
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

// Sends give[q] points to each process q (the points in runs by destination, in rank order) and
// receives take[q] from each, in rank order: one MPI_Alltoallv per field. An optional field that
// some process holds is held by all afterwards (its initial value where it was not).
template <int D>
void move_points(Particles<D>& P, const Processes& procs, const std::vector<long>& give,
                 const std::vector<long>& take) {
  const std::size_t k = static_cast<std::size_t>(procs.size());
  long mine = 0;
  for (long t : take) mine += t;
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

// Repartitions the points in slabs of the grid (the grid's blocks, box_exchange.hpp): across the
// axis along which the points spread furthest, process r holds the r-th of N equal runs of the
// points taken in order along it (by sixteenths of a cell; within the one where a cut falls, by
// rank). Points in another process's slab move there: those that crossed a cut since the last
// call, or all of a share after a change of axis. Returns whether any moved. Every process calls
// it; it costs one histogram's sum and two small gathers when no point moves.
template <int D>
bool repartition_in_slabs(Particles<D>& P, const GridGeometry<D>& g, const Processes& procs) {
  if (!procs.distributed()) return false;
  const std::size_t n = P.size(), k = static_cast<std::size_t>(procs.size()),
                    r = static_cast<std::size_t>(procs.rank());
  double ends[2 * D];
  for (int d = 0; d < D; ++d) ends[d] = INFINITY, ends[D + d] = INFINITY;
  for (std::size_t p = 0; p < n; ++p)
    for (int d = 0; d < D; ++d)
      ends[d] = std::min(ends[d], P.x[p][d]), ends[D + d] = std::min(ends[D + d], -P.x[p][d]);
  procs.min(ends, 2 * D);
  int axis = 0;
  for (int d = 1; d < D; ++d)
    if (-ends[D + d] - ends[d] > -ends[D + axis] - ends[axis]) axis = d;
  constexpr int kBinsPerCell = 16;  // the cuts fall within cells, so the shares are even
  const int bins = g.cells[static_cast<std::size_t>(axis)] * kBinsPerCell;
  const auto bin_of = [&](const Vec<D>& x) {
    const double c = std::floor((x[axis] - g.origin[axis]) / g.h * kBinsPerCell);
    return c < 0.0 ? 0 : c > bins - 1 ? bins - 1 : static_cast<int>(c);
  };
  // The points in one order over every process: by bin, then rank, then their order here. Process
  // q takes the q-th of N equal runs of it, so only the bins a cut falls in need the lower ranks'
  // counts (one gather of at most N - 1 per process).
  std::vector<long> count(static_cast<std::size_t>(bins), 0);
  for (std::size_t p = 0; p < n; ++p) ++count[static_cast<std::size_t>(bin_of(P.x[p]))];
  std::vector<long> before(static_cast<std::size_t>(bins) + 1, 0);  // points in lower bins, all
  {
    std::vector<long> all_count = count;
    procs.sum(all_count.data(), all_count.size());
    for (std::size_t c = 0; c < all_count.size(); ++c) before[c + 1] = before[c] + all_count[c];
  }
  const long total = before.back();
  const auto target = [&](std::size_t q) { return total * static_cast<long>(q) / static_cast<long>(k); };
  std::vector<int> cut_bins;  // the bins a cut falls in
  for (std::size_t q = 1; q < k; ++q) {
    const long t = target(q);
    const auto c = std::upper_bound(before.begin(), before.end(), t) - before.begin() - 1;
    if (c < bins && before[static_cast<std::size_t>(c)] < t && (cut_bins.empty() || cut_bins.back() != c))
      cut_bins.push_back(static_cast<int>(c));
  }
  std::vector<double> mine_in(k - 1, 0.0), all_in((k - 1) * k);
  for (std::size_t j = 0; j < cut_bins.size(); ++j)
    mine_in[j] = static_cast<double>(count[static_cast<std::size_t>(cut_bins[j])]);
  procs.gather(mine_in.data(), k - 1, all_in.data(), all_in.size());
  std::vector<long> next(static_cast<std::size_t>(bins),
                         0);  // per bin: the order of this rank's next point in it
  for (std::size_t c = 0; c < next.size(); ++c) next[c] = before[c];
  for (std::size_t j = 0; j < cut_bins.size(); ++j)
    for (std::size_t s = 0; s < r; ++s)
      next[static_cast<std::size_t>(cut_bins[j])] += static_cast<long>(all_in[s * (k - 1) + j]);
  std::vector<std::uint32_t> to(n);
  std::vector<long> give(k, 0);
  for (std::size_t p = 0; p < n; ++p) {
    const long at = next[static_cast<std::size_t>(bin_of(P.x[p]))]++;
    std::size_t q = 0;  // the run that holds order `at`
    while (q + 1 < k && target(q + 1) <= at) ++q;
    to[p] = static_cast<std::uint32_t>(q);
    ++give[q];
  }
  std::vector<double> gives(k), all(k * k);  // every process's gives
  for (std::size_t q = 0; q < k; ++q) gives[q] = static_cast<double>(give[q]);
  procs.gather(gives.data(), k, all.data(), all.size());
  std::vector<long> take(k);
  long moving = 0;
  for (std::size_t q = 0; q < k; ++q) {
    take[q] = static_cast<long>(all[q * k + r]);
    for (std::size_t s = 0; s < k; ++s) moving += s == q ? 0 : static_cast<long>(all[q * k + s]);
  }
  if (moving == 0) return false;
  std::vector<std::uint32_t> order(n);  // by destination, stable
  std::vector<long> at(k + 1, 0);
  for (std::size_t q = 0; q < k; ++q) at[q + 1] = at[q] + give[q];
  for (std::size_t p = 0; p < n; ++p)
    order[static_cast<std::size_t>(at[to[p]]++)] = static_cast<std::uint32_t>(p);
  P.reorder(order);
  move_points(P, procs, give, take);
  return true;
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
