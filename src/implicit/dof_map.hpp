// The unknowns of an implicit step: D displacement components at every node that carries mass
// (the active nodes), and the compressed-row pattern of the stiffness matrix, exact: two nodes
// are coupled when one block holds both — a point's stencil, or with the cell-averaged
// volumetric strain the box of nodes of a cell's points (cell_boxes.hpp). A component held by a
// wall (Dirichlet condition) keeps its row as an identity row with a zero right-hand side, so
// the matrix keeps the symmetry of the tangent and a node's D unknowns stay together (PETSc's
// block size, the multigrid's near null space).
//
// One process numbers the active nodes in flat-index order. Across processes (issue 55) each
// process knows the nodes of its box (transfer/box_exchange.hpp: the nodes its points reach, and
// a stencil's width beyond), whose masses are every process's sums, and numbers those that carry
// mass locally: the ones it owns first, then the others, each in flat order. A node is owned by
// the lowest rank whose points' blocks touch it (else by the lowest whose box holds it), and the
// unknowns' global numbers run by owner, so each process owns one run of the matrix's rows, and
// these follow the points' blocks of the grid (point_shares.hpp). Owners, global numbers and
// couplings are agreed between the processes whose boxes meet, over the boxes' star forest; no
// process holds the whole grid's unknowns. A process keeps the pattern of its own rows (every
// process's couplings: their union) and of the rows its points' blocks touch (its own
// couplings, which it sends to the rows' owners); its other rows are empty. The residual's sums
// over the processes follow the same rows (sum_rows): each owner adds the others' parts of its
// rows and sends the sums back to the processes that touch them.
#pragma once
#include <omp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "core/grid.hpp"
#include "implicit/linear_system.hpp"
#include "parallel/processes.hpp"
#include "parallel/star_forest.hpp"
#include "transfer/box_exchange.hpp"

namespace skred {

template <int D>
class DofMap {
 public:
  // The coupling blocks: `blocks` runs of Kb = Sb^D flat node indices at `block_node` (boxes
  // Sb nodes wide per axis, axis 0 fastest); the points' stencils are Sp wide (Sp <= Sb).
  // `mass` per grid node (its active nodes: mass > 0), `held` per grid node the bits c of its
  // components held by a wall. Across processes, `boxes` (set: this process's box, holding every
  // node of its blocks and their couplings) and `mass` summed over the processes in the box.
  void build(const std::int64_t* block_node, std::size_t blocks, int Sb, int Sp, const GridGeometry<D>& g,
             std::span<const double> mass, std::span<const std::uint8_t> held, int threads,
             BoxExchange<D>* boxes = nullptr) {
    const bool across = boxes && boxes->processes().distributed();
    S_ = Sb;
    W_ = 2 * Sb - 1;
    int box = 1;
    for (int d = 0; d < D; ++d) box *= W_;
    words_ = (box + 63) / 64;
    // Active nodes in flat order (across processes: those of this process's box). active_ is -1
    // but at the previous build's active nodes, which alone are reset (O(the box), not the grid).
    if (active_.size() != mass.size())
      active_.assign(mass.size(), -1);
    else
      for (const std::int64_t i : nodes_) active_[static_cast<std::size_t>(i)] = -1;
    nodes_.clear();
    const auto add = [&](std::size_t i) {
      if (!(mass[i] > 0.0)) return;
      active_[i] = static_cast<std::int32_t>(nodes_.size());
      nodes_.push_back(static_cast<std::int64_t>(i));
    };
    if (across) {
      const NodeBox<D>& box = boxes->boxes()[static_cast<std::size_t>(boxes->processes().rank())];
      std::size_t stride[D];
      for (int d = 0; d < D; ++d) stride[d] = g.stride(d);
      const long rows = box_rows(box), width = box.hi[0] - box.lo[0] + 1;
      for (long r = 0; r < rows; ++r)  // (the rows in ascending flat order)
        for (long j = 0; j < width; ++j) add(box_row_start(box, stride, r) + static_cast<std::size_t>(j));
    } else {
      for (std::size_t i = 0; i < mass.size(); ++i) add(i);
    }
    offsets(Sp, pair_offset_);
    offsets(Sb, box_offset_);
    int K = 1;
    for (int d = 0; d < D; ++d) K *= Sb;
    // Which offsets each active node couples to.
    mask_.assign(nodes_.size() * static_cast<std::size_t>(words_), 0);
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::size_t p = 0; p < blocks; ++p)
      for (int k = 0; k < K; ++k) {
        const std::int32_t a = active_[static_cast<std::size_t>(block_node[p * K + k])];
        if (a < 0) continue;
        std::uint64_t* m = &mask_[static_cast<std::size_t>(a) * words_];
        for (int l = 0; l < K; ++l) {
          if (active_[static_cast<std::size_t>(block_node[p * K + l])] < 0) continue;
          const int o = box_offset_[static_cast<std::size_t>(k * K + l)];
          __atomic_fetch_or(&m[o / 64], std::uint64_t{1} << (o % 64), __ATOMIC_RELAXED);
        }
      }
    first_node_ = 0;
    end_node_ = nodes_.size();
    first_global_ = 0;
    global_nodes_ = static_cast<long>(nodes_.size());
    distributed_ = across;
    global_.clear();
    if (distributed_) own_rows_by_process(*boxes);
    coupled_ = true;  // (the union of the couplings: owned rows' masks, and one process's)
    {
      int centre = 0;
      for (int d = 0, pw = 1; d < D; ++d, pw *= W_) centre += (S_ - 1) * pw;
      bool all = true;
      for (std::size_t a = first_node_; a < end_node_; ++a)
        all = all && ((mask_[a * words_ + centre / 64] >> (centre % 64)) & 1u);
      coupled_ = !(across ? boxes->processes().any(!all) : !all);
    }
    held_.assign(nodes_.size(), 0);
    for (std::size_t a = 0; a < nodes_.size(); ++a) held_[a] = held[static_cast<std::size_t>(nodes_[a])];
    // Rows: node a's D rows each hold D entries per coupled node, in the offsets' order (one
    // process: ascending columns).
    const std::size_t rows = nodes_.size() * D;
    pattern_.row_start.assign(rows + 1, 0);
    std::vector<int> count(nodes_.size());
    for (std::size_t a = 0; a < nodes_.size(); ++a) {
      int c = 0;
      for (int w = 0; w < words_; ++w) c += std::popcount(mask_[a * words_ + w]);
      count[a] = c;
      for (int r = 0; r < D; ++r) pattern_.row_start[a * D + r + 1] = c * D;
    }
    for (std::size_t r = 0; r < rows; ++r) pattern_.row_start[r + 1] += pattern_.row_start[r];
    pattern_.column.resize(static_cast<std::size_t>(pattern_.row_start[rows]));
    std::vector<std::int64_t> offset_step(static_cast<std::size_t>(box));
    for (int o = 0; o < box; ++o) {
      std::int64_t step = 0;
      for (int d = 0, r = o; d < D; ++d, r /= W_)
        step += static_cast<std::int64_t>(r % W_ - (Sb - 1)) * static_cast<std::int64_t>(g.stride(d));
      offset_step[static_cast<std::size_t>(o)] = step;
    }
    fill_columns(offset_step, threads);
  }

 private:
  // Fills the column indices, given each offset's flat-index step (the grid's strides).
  void fill_columns(const std::vector<std::int64_t>& offset_step, int threads) {
    const std::size_t na = nodes_.size();
    bool outside = false;
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::size_t a = 0; a < na; ++a) {
      std::int32_t* col = &pattern_.column[static_cast<std::size_t>(pattern_.row_start[a * D])];
      int j = 0;
      for (int w = 0; w < words_; ++w)
        for (std::uint64_t bits = mask_[a * words_ + w]; bits; bits &= bits - 1) {
          const int o = 64 * w + std::countr_zero(bits);
          const std::int64_t b = nodes_[a] + offset_step[static_cast<std::size_t>(o)];
          const std::int32_t ab = active_[static_cast<std::size_t>(b)];
          if (ab < 0) {  // (ImplicitSolver::set_box's box holds every coupled node)
#pragma omp atomic write
            outside = true;
          }
          for (int c = 0; c < D; ++c) col[j++] = ab * D + c;
        }
      const int len = j;
      for (int r = 1; r < D; ++r)
        for (int i = 0; i < len; ++i) col[r * len + i] = col[i];
    }
    if (outside) throw std::logic_error("DofMap: a node coupled to an active one lies outside the box");
  }

 public:
  // This process's unknowns (one process: all of them) and its active nodes.
  int dofs() const { return static_cast<int>(nodes_.size()) * D; }
  std::size_t active_nodes() const { return nodes_.size(); }
  // The whole system's active nodes, and the global number of this process's active node a
  // (one process: a). Its own nodes are [first_global, first_global + end_node).
  long global_nodes() const { return global_nodes_; }
  long global_node(std::size_t a) const { return distributed_ ? global_[a] : static_cast<long>(a); }
  long first_global() const { return first_global_; }
  // Across processes: each local row's row in the whole system (LinearSystem::set_pattern).
  GlobalRows global_rows() const {
    if (static_cast<double>(global_nodes_) * D > 2147483647.0)
      throw std::runtime_error(
          "the implicit system has more unknowns than this PETSc's 32-bit indices count");
    GlobalRows rows;
    rows.owned = static_cast<int>(D * end_node_);
    rows.size = static_cast<int>(D * global_nodes_);
    rows.row.resize(nodes_.size() * D);
    for (std::size_t a = 0; a < nodes_.size(); ++a)
      for (int c = 0; c < D; ++c) rows.row[a * D + c] = static_cast<std::int32_t>(global_node(a) * D + c);
    return rows;
  }
  // Active index of grid node i, -1 when it carries no mass.
  std::int32_t active(std::size_t i) const { return active_[i]; }
  std::int64_t node(std::size_t a) const { return nodes_[a]; }
  bool held(std::size_t a, int c) const { return (held_[a] >> c) & 1u; }
  const SparsePattern& pattern() const { return pattern_; }
  int box_width() const { return W_; }
  // Whether every active node's own block is in the pattern (a node no block holds has none):
  // the same answer on every process.
  bool every_node_coupled_to_itself() const { return coupled_; }
  // Across processes: the sums over the processes of per-row values (D per active node, in the
  // unknowns' order) in the rows this process owns or its blocks touch, each process having put
  // its own parts there; the owner adds the others' parts to its own in a fixed order and sends
  // the sums back (a star forest). The other rows are left as they are. Collective; nothing for
  // one process.
  void sum_rows(double* v) {
    if (!distributed_) return;
    leaf_values_.resize(leaf_node_.size() * D);
    for (std::size_t k = 0; k < leaf_node_.size(); ++k)
      std::copy_n(v + leaf_node_[k] * D, D, leaf_values_.data() + k * D);
    double* own = v + first_node_ * D;
    rows_.reduce(D, leaf_values_.data(), own);
    rows_.broadcast(D, own, leaf_values_.data());
    for (std::size_t k = 0; k < leaf_node_.size(); ++k)
      std::copy_n(leaf_values_.data() + k * D, D, v + leaf_node_[k] * D);
  }
  // Across processes: the nodes this process's blocks touch that another owns (ascending).
  const std::vector<std::size_t>& touched_not_owned() const { return leaf_node_; }
  // The active nodes this process owns, [first_node, end_node) (all of them for one process;
  // across processes first_node is 0); their rows are [D first_node, D end_node).
  std::size_t first_node() const { return first_node_; }
  std::size_t end_node() const { return end_node_; }
  // Position in the values of entry (row a D + r, column b D + c) for the block coupling
  // active node a to the node at offset o from it: row_entry(a, r, o) + c.
  std::int32_t row_entry(std::size_t a, int r, int o) const {
    const std::uint64_t* m = &mask_[a * words_];
    int rank = 0;
    for (int w = 0; w < o / 64; ++w) rank += std::popcount(m[w]);
    rank += std::popcount(m[o / 64] & ((std::uint64_t{1} << (o % 64)) - 1));
    const std::int32_t start = pattern_.row_start[a * D + r];
    return start + rank * D;
  }
  // Offset of node l from node k of one point's stencil (K nodes), and of one cell's box.
  int pair_offset(int k, int l, int K) const { return pair_offset_[static_cast<std::size_t>(k * K + l)]; }
  int box_offset(int i, int j, int K) const { return box_offset_[static_cast<std::size_t>(i * K + j)]; }

 private:
  // Across processes: the owners, the numbering by owner and each row's mask, the union of the
  // processes' in the rows this one owns, its own in the others (see the top of the file); each
  // agreed with the processes whose boxes hold the node, over the boxes' star forest.
  void own_rows_by_process(BoxExchange<D>& boxes) {
    const Processes& procs = boxes.processes();
    const std::size_t na = nodes_.size(), w = static_cast<std::size_t>(words_);
    const double rank = procs.rank(), none = procs.size();
    // The owner: the least over the holders of rank (its blocks touch the node) or none + rank.
    std::vector<double> key(na);
    std::vector<std::uint8_t> touched(na, 0);
    for (std::size_t a = 0; a < na; ++a) {
      for (std::size_t k = 0; k < w; ++k) touched[a] = touched[a] || mask_[a * w + k] != 0;
      key[a] = touched[a] ? rank : none + rank;
    }
    boxes.combine_slots(StarForest::Combine::Min, active_, key, INFINITY);
    std::vector<int> owner(na);
    std::size_t owned = 0;
    for (std::size_t a = 0; a < na; ++a) {
      owner[a] = static_cast<int>(key[a] < none ? key[a] : key[a] - none);
      owned += owner[a] == procs.rank();
    }
    // The union of the holders' couplings.
    std::vector<std::uint64_t> all(mask_);
    boxes.unite_bits(
        words_,
        [&](std::size_t i, std::uint64_t* at) {
          const std::int32_t a = active_[i];
          for (std::size_t k = 0; k < w; ++k) at[k] = a >= 0 ? mask_[static_cast<std::size_t>(a) * w + k] : 0;
        },
        [&](std::size_t i, const std::uint64_t* at) {
          if (const std::int32_t a = active_[i]; a >= 0)
            std::copy_n(at, w, &all[static_cast<std::size_t>(a) * w]);
        });
    // The global numbers: each owner's run, in flat order, sent to the other holders.
    first_global_ = procs.offset(static_cast<long>(owned));
    global_nodes_ = procs.sum_of(static_cast<long>(owned));
    std::vector<double> number(na, -1.0);
    for (std::size_t a = 0, k = 0; a < na; ++a)
      if (owner[a] == procs.rank()) number[a] = static_cast<double>(first_global_ + static_cast<long>(k++));
    boxes.combine_slots(StarForest::Combine::Max, active_, number, -1.0);
    std::vector<double> firsts(static_cast<std::size_t>(procs.size()));
    const double mine = static_cast<double>(first_global_);
    procs.gather(&mine, 1, firsts.data(), firsts.size());
    // The local order: the owned nodes, then the others.
    std::vector<std::int64_t> nodes(na);
    std::vector<std::uint64_t> mask(na * w);
    global_.assign(na, 0);
    std::vector<int> leaf_rank;
    std::vector<long> leaf_index;
    leaf_node_.clear();
    std::size_t next_owned = 0, next_other = owned;
    for (std::size_t a = 0; a < na; ++a) {
      if (number[a] < 0.0) throw std::logic_error("DofMap: an active node without a global number");
      const bool own = owner[a] == procs.rank();
      const std::size_t to = own ? next_owned++ : next_other++;
      nodes[to] = nodes_[a];
      global_[to] = static_cast<long>(number[a]);
      active_[static_cast<std::size_t>(nodes_[a])] = static_cast<std::int32_t>(to);
      const std::uint64_t* from = own ? &all[a * w] : &mask_[a * w];
      std::copy(from, from + w, &mask[to * w]);
      if (touched[a] && !own) {  // a leaf of the row sums: the owner's root of its global number
        leaf_node_.push_back(to);
        leaf_rank.push_back(owner[a]);
        leaf_index.push_back(global_[to] - static_cast<long>(firsts[static_cast<std::size_t>(owner[a])]));
      }
    }
    nodes_.swap(nodes);
    mask_.swap(mask);
    first_node_ = 0;
    end_node_ = owned;
    rows_.connect(procs, static_cast<long>(owned), leaf_rank, leaf_index);
  }

  // The offset index of node l seen from node k of a block S wide:
  // o = sum_d (l_d - k_d + S_ - 1) W^d, in the coupling box of width S_.
  void offsets(int S, std::vector<int>& table) const {
    int K = 1;
    for (int d = 0; d < D; ++d) K *= S;
    table.assign(static_cast<std::size_t>(K * K), 0);
    for (int k = 0; k < K; ++k)
      for (int l = 0; l < K; ++l) {
        int o = 0, pw = 1, rk = k, rl = l;
        for (int d = 0; d < D; ++d) {
          o += (rl % S - rk % S + S_ - 1) * pw;
          pw *= W_;
          rk /= S;
          rl /= S;
        }
        table[static_cast<std::size_t>(k * K + l)] = o;
      }
  }

  int S_ = 2, W_ = 3, words_ = 1;
  std::vector<std::int32_t> active_;
  std::vector<std::int64_t> nodes_;
  std::vector<std::uint8_t> held_;
  std::vector<std::uint64_t> mask_;
  std::vector<int> pair_offset_, box_offset_;
  std::size_t first_node_ = 0, end_node_ = 0;
  long first_global_ = 0, global_nodes_ = 0;
  std::vector<long> global_;  // across processes: each active node's global number
  bool coupled_ = true, distributed_ = false;
  StarForest rows_;                     // sum_rows: a root per owned node, a leaf per touched one
  std::vector<std::size_t> leaf_node_;  // the touched nodes another process owns
  std::vector<double> leaf_values_;
  SparsePattern pattern_;
};

}  // namespace skred
