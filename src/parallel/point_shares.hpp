// Each process's share of the points of a distributed run (processes.hpp). A run's set-up builds
// each process's cell columns only (run/point_setup.hpp); a resume on another count, the bench and
// the tests keep a contiguous run of all the points in their order (keep_share: points
// [n r / N, n (r + 1) / N) of process r of N). The run then keeps them in blocks of the grid cut
// by recursive bisection (repartition_in_blocks), so that each process's points, and the box of
// nodes they reach, lie together, and points move to a neighbour as they cross a cut.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/grid.hpp"
#include "core/particles.hpp"
#include "parallel/processes.hpp"
#include "parallel/star_forest.hpp"

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

// Moves points between processes over a star forest (star_forest.hpp): the points here are the
// roots, and the points this process takes are its leaves: from[2 q] points from process q, the
// run of q's points that starts at from[2 q + 1], in rank order. One broadcast per field. An
// optional field that some process holds is held by all afterwards (its initial value where it
// was not).
template <int D>
void move_points(Particles<D>& P, const Processes& procs, const std::vector<long>& from) {
  const std::size_t k = static_cast<std::size_t>(procs.size());
  std::vector<int> rank;
  std::vector<long> index;
  for (std::size_t q = 0; q < k; ++q)
    for (long j = 0; j < from[2 * q]; ++j)
      rank.push_back(static_cast<int>(q)), index.push_back(from[2 * q + 1] + j);
  const std::size_t held = P.size();
  StarForest forest;
  forest.connect(procs, static_cast<long>(held), rank, index);
  std::vector<double> present;  // per field: held here (1) or not
  P.for_each_field(
      [&](const auto& f, const auto& a) { present.push_back(f.optional && a.empty() ? 0.0 : 1.0); });
  procs.max(present.data(), present.size());
  std::size_t at = 0;
  P.for_each_field([&](const auto& f, auto& a) {
    if (present[at++] == 0.0) return;
    using T = typename std::decay_t<decltype(f)>::value_type;
    if (a.empty()) a.assign(held, f.initial());  // (an optional field another process holds)
    std::decay_t<decltype(a)> b(rank.size());
    forest.broadcast_bytes(sizeof(T), a.data(), b.data());  // (plain values: numbers, fixed-size Eigen)
    a.swap(b);
  });
}

// Repartitions the points in blocks of the grid by recursive bisection (the grid's blocks,
// box_exchange.hpp). The processes [0, N) are halved into [0, N/2) and [N/2, N), and the points
// are cut across the axis along which they spread furthest: taken in order along it (by
// sixteenths of a cell; within the one where the cut falls, by rank, then by their order here),
// the first ones go to the lower half, as many as its processes' runs of the whole, so that
// process r ends with points [n r / N, n (r + 1) / N) of the n, to one. Each half is cut again
// across its own points' widest axis, until each holds one process. At 2 processes the blocks
// are slabs. Points in another process's block move there: those that crossed a cut since the
// last call, or many after an axis changed. Returns whether any moved. Every process calls it; it
// costs log2 N histograms' sums, small gathers and an all-to-all of two numbers when no point moves.
template <int D>
bool repartition_in_blocks(Particles<D>& P, const GridGeometry<D>& g, const Processes& procs) {
  if (!procs.distributed()) return false;
  const std::size_t n = P.size(), k = static_cast<std::size_t>(procs.size()),
                    r = static_cast<std::size_t>(procs.rank());
  constexpr int kBinsPerCell = 16;  // the cuts fall within cells, so the shares are even
  struct Group {
    int a, b;  // processes [a, b)
  };
  std::vector<Group> groups{{0, static_cast<int>(k)}};
  std::vector<std::uint32_t> in(n, 0);  // each point's group
  long all = static_cast<long>(n);
  procs.sum(&all, 1);
  const auto target = [&](int q) { return all * q / static_cast<long>(k); };  // points before q's run
  for (bool split = true; split;) {
    const std::size_t G = groups.size();
    // The extent of each group's points, and the axis each group is cut across.
    std::vector<double> ends(2 * D * G, INFINITY);  // per group: lo per axis, then -hi
    for (std::size_t p = 0; p < n; ++p)
      for (int d = 0; d < D; ++d) {
        double* e = &ends[2 * D * in[p]];
        e[d] = std::min(e[d], P.x[p][d]), e[D + d] = std::min(e[D + d], -P.x[p][d]);
      }
    procs.min(ends.data(), ends.size());
    std::vector<int> axis(G, 0);
    std::vector<long> base(G, 0);                  // each group's first bin along its axis
    std::vector<std::size_t> first_bin(G + 1, 0);  // each group's histogram in one array
    for (std::size_t j = 0; j < G; ++j) {
      const double* e = &ends[2 * D * j];
      for (int d = 1; d < D; ++d)
        if (-e[D + d] - e[d] > -e[D + axis[j]] - e[axis[j]]) axis[j] = d;
      long bins = 0;  // over the group's points' extent only
      if (groups[j].b - groups[j].a > 1 && e[axis[j]] <= -e[D + axis[j]]) {
        const auto bin = [&](double x) {
          return static_cast<long>(std::floor((x - g.origin[axis[j]]) / g.h * kBinsPerCell));
        };
        base[j] = bin(e[axis[j]]);
        bins = bin(-e[D + axis[j]]) - base[j] + 1;
      }
      first_bin[j + 1] = first_bin[j] + static_cast<std::size_t>(bins);
    }
    const auto bin_of = [&](std::size_t j, const Vec<D>& x) {
      const long bins = static_cast<long>(first_bin[j + 1] - first_bin[j]);
      const long c =
          static_cast<long>(std::floor((x[axis[j]] - g.origin[axis[j]]) / g.h * kBinsPerCell)) - base[j];
      return first_bin[j] + static_cast<std::size_t>(std::clamp(c, 0L, bins - 1));
    };
    std::vector<long> count(first_bin[G], 0);
    for (std::size_t p = 0; p < n; ++p)
      if (groups[in[p]].b - groups[in[p]].a > 1) ++count[bin_of(in[p], P.x[p])];
    std::vector<long> before(first_bin[G] + 1, 0);  // per bin: the group's points in lower bins, all
    {
      std::vector<long> all_count = count;
      procs.sum(all_count.data(), all_count.size());
      for (std::size_t j = 0; j < G; ++j)
        for (std::size_t c = first_bin[j]; c < first_bin[j + 1]; ++c)
          before[c + 1] = before[c] + all_count[c];
    }
    // Each halved group's cut: `cut` points of it go to the lower half; the bin it falls in.
    std::vector<long> cut(G, 0);
    std::vector<double> mine_in(G, 0.0), all_in(G * k);  // this process's points in the cut bin
    std::vector<std::size_t> cut_bin(G, SIZE_MAX);
    for (std::size_t j = 0; j < G; ++j) {
      if (groups[j].b - groups[j].a < 2 || first_bin[j] == first_bin[j + 1]) continue;  // (no points)
      const int m = (groups[j].a + groups[j].b) / 2;
      cut[j] = target(m) - target(groups[j].a);
      const auto lo = before.begin() + static_cast<long>(first_bin[j]),
                 hi = before.begin() + static_cast<long>(first_bin[j + 1]);
      const auto c = static_cast<std::size_t>(std::upper_bound(lo, hi, before[first_bin[j]] + cut[j]) -
                                              before.begin() - 1);
      if (c < first_bin[j + 1] && before[c] < before[first_bin[j]] + cut[j]) {
        cut_bin[j] = c;
        mine_in[j] = static_cast<double>(count[c]);
      }
    }
    procs.gather(mine_in.data(), G, all_in.data(), all_in.size());
    std::vector<long> next(before.begin(),
                           before.end() - 1);  // per bin: the order of this rank's next point in it
    for (std::size_t j = 0; j < G; ++j) {
      if (cut_bin[j] == SIZE_MAX) continue;
      for (std::size_t q = 0; q < r; ++q) next[cut_bin[j]] += static_cast<long>(all_in[q * G + j]);
    }
    // The next level's groups: group j's lower half is halved[lower[j]], its upper the one after.
    std::vector<Group> halved;
    std::vector<std::uint32_t> lower(G);
    for (std::size_t j = 0; j < G; ++j) {
      lower[j] = static_cast<std::uint32_t>(halved.size());
      const Group& h = groups[j];
      if (h.b - h.a < 2) {
        halved.push_back(h);
        continue;
      }
      const int m = (h.a + h.b) / 2;
      halved.push_back({h.a, m});
      halved.push_back({m, h.b});
    }
    for (std::size_t p = 0; p < n; ++p) {
      const std::uint32_t j = in[p];
      if (groups[j].b - groups[j].a < 2) {
        in[p] = lower[j];
        continue;
      }
      const long at = next[bin_of(j, P.x[p])]++ - before[first_bin[j]];  // order within the group
      in[p] = lower[j] + (at < cut[j] ? 0 : 1);
    }
    split = false;
    for (const Group& h : halved) split = split || h.b - h.a > 1;
    groups.swap(halved);
  }
  std::vector<std::uint32_t> to(n);
  std::vector<long> give(k, 0);
  for (std::size_t p = 0; p < n; ++p) {
    to[p] = static_cast<std::uint32_t>(groups[in[p]].a);
    ++give[to[p]];
  }
  std::vector<long> at(k + 1, 0);  // where each destination's run starts, in order by destination
  for (std::size_t q = 0; q < k; ++q) at[q + 1] = at[q] + give[q];
  // Each process learns how many points every other gives it, and where that run starts in the
  // giver's order.
  std::vector<long> offer(2 * k), from(2 * k);
  for (std::size_t q = 0; q < k; ++q) offer[2 * q] = give[q], offer[2 * q + 1] = at[q];
  procs.all_to_all(offer.data(), 2, from.data());
  if (procs.sum_of(static_cast<long>(n) - give[r]) == 0) return false;
  std::vector<std::uint32_t> order(n);  // by destination, stable
  for (std::size_t p = 0; p < n; ++p)
    order[static_cast<std::size_t>(at[to[p]]++)] = static_cast<std::uint32_t>(p);
  P.reorder(order);
  move_points(P, procs, from);
  return true;
}

}  // namespace skred
