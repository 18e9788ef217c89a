// The grid's blocks of a distributed run (issue 55): each process works on the box of nodes its
// own points reach (node_box.hpp), and a grid sum is completed only where boxes overlap, between
// the processes whose boxes meet, instead of over the whole grid in every process. The points
// are kept in blocks of the grid (point_shares.hpp, repartition_in_blocks), so the overlaps are the
// layers where neighbouring blocks meet: ghost layers as wide as the kernel's reach.
//
// A node held by several processes is owned by the lowest rank whose box holds it; for a node of
// its own box a process asks only its neighbours, the processes whose boxes meet its own (found
// once per setting). The shared nodes form a PETSc star forest (parallel/star_forest.hpp): a root
// at the owner, a leaf at each other holder. A sum reduces the leaves' parts into the owner's, which sends
// the sum back, so every holder has the same bits. The forest is rebuilt only when a box changed. Node totals
// (the walls' and contact's work) count each node once, in the process that `counts` it.
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/grid.hpp"
#include "parallel/processes.hpp"
#include "parallel/star_forest.hpp"
#include "transfer/node_box.hpp"

namespace skred {

template <int D>
class BoxExchange {
 public:
  // Every process's box (collective: one allgather).
  void set(const GridGeometry<D>& g, const NodeBox<D>& mine, const Processes& procs) {
    procs_ = procs;
    for (int d = 0; d < D; ++d) nodes_[d] = g.nodes(d);
    const std::size_t k = static_cast<std::size_t>(procs.size());
    double ends[2 * D];
    for (int d = 0; d < D; ++d) ends[d] = mine.lo[d], ends[D + d] = mine.hi[d];
    all_.resize(2 * D * k);
    procs.gather(ends, 2 * D, all_.data(), all_.size());

    bool same = forest_set_ && boxes_.size() == k;
    boxes_.resize(k);
    for (std::size_t q = 0; q < k; ++q)
      for (int d = 0; d < D; ++d) {
        const int lo = static_cast<int>(all_[2 * D * q + static_cast<std::size_t>(d)]);
        const int hi = static_cast<int>(all_[2 * D * q + static_cast<std::size_t>(D + d)]);
        same = same && boxes_[q].lo[d] == lo && boxes_[q].hi[d] == hi;
        boxes_[q].lo[d] = lo, boxes_[q].hi[d] = hi;
      }
    if (!same) {  // (every process sees the same boxes: all rebuild, or none)
      neighbours_.clear();
      for (std::size_t q = 0; q < k; ++q)
        if (meet(boxes_[q], boxes_[static_cast<std::size_t>(procs.rank())]))
          neighbours_.push_back(static_cast<int>(q));
      set_forest();
    }
  }
  const Processes& processes() const { return procs_; }
  const std::vector<NodeBox<D>>& boxes() const { return boxes_; }
  // This process's box (set).
  const NodeBox<D>& own_box() const { return boxes_[static_cast<std::size_t>(procs_.rank())]; }

  // Whether this process counts node ij in the grid's totals: it is the lowest rank whose box,
  // less two layers on the sides that are not the grid's ends, holds it. Every node a point
  // reaches is so held by the point's process (reach_of leaves three layers beyond any stencil),
  // and there the neighbours a node phase reads (the mass gradient, two nodes around) are in the
  // box and summed.
  bool counts(std::size_t i) const {
    const auto ij = unflatten(i);
    for (int q : neighbours_)  // (a box that holds a node of this one meets it)
      if (q <= procs_.rank() && inside(interior(boxes_[static_cast<std::size_t>(q)]), ij))
        return q == procs_.rank();
    return false;
  }

  // The sum over the processes of per-node fields, `per` doubles a node: pack(i, at) writes
  // node i's part, set(i, at) replaces it with the sum. Collective: a reduction and a broadcast
  // over the star forest.
  template <class Pack, class Set>
  void sum(int per, Pack&& pack, Set&& set) {
    combine(per, StarForest::Combine::Sum, pack, set);
  }
  // The same with the least or greatest of the holders' values instead of their sum.
  template <class Pack, class Set>
  void combine(int per, StarForest::Combine how, Pack&& pack, Set&& set) {
    exchange(per, root_data_, leaf_data_, pack, set,
             [&](const double* leaf, double* root) { forest_.reduce(per, leaf, root, how); });
  }
  // The same for values kept by slot: node i's is v[slot[i]] (slot[i] < 0: none here, `absent`
  // sent for it).
  void combine_slots(StarForest::Combine how, const std::vector<std::int32_t>& slot, std::vector<double>& v,
                     double absent) {
    combine(
        1, how,
        [&](std::size_t i, double* at) {
          at[0] = slot[i] >= 0 ? v[static_cast<std::size_t>(slot[i])] : absent;
        },
        [&](std::size_t i, const double* at) {
          if (slot[i] >= 0) v[static_cast<std::size_t>(slot[i])] = at[0];
        });
  }
  // The union of per-node bit sets, `per` words a node.
  template <class Pack, class Set>
  void unite_bits(int per, Pack&& pack, Set&& set) {
    exchange(per, root_bits_, leaf_bits_, pack, set,
             [&](const std::uint64_t* leaf, std::uint64_t* root) { forest_.reduce_bits(per, leaf, root); });
  }

  // The first process gets every node's value where another process owns it (for a file it
  // writes of the whole grid): pack(i, at) writes node i's, set(i, at) takes it. Collective: a
  // broadcast over a star forest whose roots are each process's owned nodes and whose leaves are
  // in the first process.
  template <class Pack, class Set>
  void gather_to_first(int per, Pack&& pack, Set&& set) {
    const int r = procs_.rank(), k = procs_.size();
    const std::size_t n = static_cast<std::size_t>(per);
    const auto& mine = boxes_[static_cast<std::size_t>(r)];
    root_data_.clear();
    if (r > 0)
      walk(mine, mine, [&](std::size_t i) {
        if (own_owner(i) != r) return;
        root_data_.resize(root_data_.size() + n);
        pack(i, root_data_.data() + root_data_.size() - n);
      });
    std::vector<int> rank;
    std::vector<long> index;
    if (r == 0)
      for (int q = 1; q < k; ++q) {
        const auto& box = boxes_[static_cast<std::size_t>(q)];
        long j = 0;
        walk(box, box, [&](std::size_t i) {
          if (owner(i) == q) rank.push_back(q), index.push_back(j++);
        });
      }
    StarForest to_first;
    to_first.connect(procs_, static_cast<long>(root_data_.size() / n), rank, index);
    leaf_data_.resize(rank.size() * n);
    to_first.broadcast(per, root_data_.data(), leaf_data_.data());
    if (r > 0) return;
    std::size_t at = 0;
    for (int q = 1; q < k; ++q) {
      const auto& box = boxes_[static_cast<std::size_t>(q)];
      walk(box, box, [&](std::size_t i) {
        if (owner(i) != q) return;
        set(i, leaf_data_.data() + at);
        at += n;
      });
    }
  }

 private:
  // Packs the shared nodes' values, reduces the leaves into the roots, broadcasts the roots back.
  template <class T, class Pack, class Set, class Reduce>
  void exchange(int per, std::vector<T>& roots, std::vector<T>& leaves, Pack& pack, Set& set,
                Reduce&& reduce) {
    const std::size_t n = static_cast<std::size_t>(per);
    roots.resize(roots_.size() * n);
    leaves.resize(leaves_.size() * n);
    for (std::size_t k = 0; k < roots_.size(); ++k)
      pack(static_cast<std::size_t>(roots_[k]), roots.data() + k * n);
    for (std::size_t k = 0; k < leaves_.size(); ++k)
      pack(static_cast<std::size_t>(leaves_[k]), leaves.data() + k * n);
    reduce(leaves.data(), roots.data());
    for (std::size_t k = 0; k < roots_.size(); ++k)
      set(static_cast<std::size_t>(roots_[k]), roots.data() + k * n);
    if constexpr (std::is_same_v<T, double>)
      forest_.broadcast(per, roots.data(), leaves.data());
    else
      forest_.broadcast_bytes(n * sizeof(T), roots.data(), leaves.data());
    for (std::size_t k = 0; k < leaves_.size(); ++k)
      set(static_cast<std::size_t>(leaves_[k]), leaves.data() + k * n);
  }
  static bool inside(const NodeBox<D>& b, const std::array<int, D>& ij) {
    for (int d = 0; d < D; ++d)
      if (ij[d] < b.lo[d] || ij[d] > b.hi[d]) return false;
    return true;
  }
  NodeBox<D> interior(NodeBox<D> b) const {
    for (int d = 0; d < D; ++d) {
      if (b.lo[d] > 0) b.lo[d] += 2;
      if (b.hi[d] < nodes_[d] - 1) b.hi[d] -= 2;
    }
    return b;
  }
  std::array<int, D> unflatten(std::size_t i) const {
    std::array<int, D> ij{};
    for (int d = 0; d < D; ++d) {
      ij[d] = static_cast<int>(i % static_cast<std::size_t>(nodes_[d]));
      i /= static_cast<std::size_t>(nodes_[d]);
    }
    return ij;
  }
  static bool meet(const NodeBox<D>& a, const NodeBox<D>& b) {
    for (int d = 0; d < D; ++d)
      if (std::max(a.lo[d], b.lo[d]) > std::min(a.hi[d], b.hi[d])) return false;
    return true;
  }
  // The lowest rank whose box holds node i (any node: every box is asked).
  int owner(std::size_t i) const {
    const auto ij = unflatten(i);
    for (std::size_t q = 0; q < boxes_.size(); ++q)
      if (inside(boxes_[q], ij)) return static_cast<int>(q);
    return -1;
  }
  // The same for a node of this process's box: only its neighbours' boxes can hold it.
  int own_owner(std::size_t i) const {
    const auto ij = unflatten(i);
    for (int q : neighbours_)
      if (inside(boxes_[static_cast<std::size_t>(q)], ij)) return q;
    return -1;
  }
  // fn(i) for the nodes of a and b both, in one order that both processes follow.
  template <class Fn>
  void walk(const NodeBox<D>& a, const NodeBox<D>& b, Fn&& fn) const {
    NodeBox<D> c;
    for (int d = 0; d < D; ++d) c.lo[d] = std::max(a.lo[d], b.lo[d]), c.hi[d] = std::min(a.hi[d], b.hi[d]);
    if (c.empty()) return;
    std::size_t stride[D];
    stride[0] = 1;
    for (int d = 1; d < D; ++d) stride[d] = stride[d - 1] * static_cast<std::size_t>(nodes_[d - 1]);
    const long rows = box_rows(c), width = c.hi[0] - c.lo[0] + 1;
    for (long row = 0; row < rows; ++row) {
      const std::size_t first = box_row_start(c, stride, row);
      for (long j = 0; j < width; ++j) fn(first + static_cast<std::size_t>(j));
    }
  }
  // The star forest of the shared nodes: in this box, those it owns that another box holds
  // (roots) and those another process owns (leaves).
  void set_forest() {
    const int r = procs_.rank();
    const auto& mine = boxes_[static_cast<std::size_t>(r)];
    roots_.clear();
    leaves_.clear();
    for (int q : neighbours_) {
      if (q == r) continue;
      walk(mine, boxes_[static_cast<std::size_t>(q)],
           [&](std::size_t i) { (own_owner(i) == r ? roots_ : leaves_).push_back(static_cast<long>(i)); });
    }
    for (auto* v : {&roots_, &leaves_}) {
      std::sort(v->begin(), v->end());
      v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    long nodes = 1;
    for (int d = 0; d < D; ++d) nodes *= nodes_[d];
    forest_.match_nodes(procs_, nodes, roots_, leaves_);
    forest_set_ = true;
  }

  Processes procs_;
  std::array<int, D> nodes_{};
  std::vector<NodeBox<D>> boxes_;
  std::vector<int> neighbours_;  // the ranks whose boxes meet this one's, ascending (itself too)
  std::vector<double> all_;
  StarForest forest_;
  bool forest_set_ = false;
  std::vector<long> roots_, leaves_;  // global node numbers, ascending
  std::vector<double> root_data_, leaf_data_;
  std::vector<std::uint64_t> root_bits_, leaf_bits_;
};

}  // namespace skred
