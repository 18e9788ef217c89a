// The implicit integrator's unknowns across processes (issue 55, dof_map.hpp): each process holds
// the unknowns of its box of the grid only; each active node is owned by the lowest rank whose
// points' blocks touch it, the nodes are numbered by owner so each process owns one run of rows,
// and a process keeps the pattern of its own rows (every process's couplings) and of the rows its
// blocks touch (its own), not the whole matrix's.
// Checked on a strip of linear cells (2 x 2 nodes each) cut into N runs of columns, against the
// same cells' DofMap on one process.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "core/grid.hpp"
#include "implicit/dof_map.hpp"
#include "implicit/linear_system.hpp"
#include "parallel/processes.hpp"
#include "transfer/box_exchange.hpp"

namespace skred {
namespace {

constexpr int kCellsX = 40, kCellsY = 10;

// The cells' blocks (their 4 nodes, axis 0 fastest) with ix in [from, to).
std::vector<std::int64_t> cell_blocks(const GridGeometry<2>& g, int from, int to) {
  std::vector<std::int64_t> b;
  for (int iy = 0; iy < kCellsY; ++iy)
    for (int ix = from; ix < to; ++ix)
      for (int k = 0; k < 4; ++k) {
        const int i = ix + 1 + (k & 1), j = iy + 1 + (k >> 1);
        b.push_back(static_cast<std::int64_t>(i) + static_cast<std::int64_t>(j) * g.nodes(0));
      }
  return b;
}

// Row `row` of a pattern as the set of (node, component) pairs of its columns.
std::set<std::pair<std::int64_t, int>> row_nodes(const DofMap<2>& m, int row) {
  std::set<std::pair<std::int64_t, int>> s;
  const SparsePattern& p = m.pattern();
  for (std::int32_t e = p.row_start[static_cast<std::size_t>(row)];
       e < p.row_start[static_cast<std::size_t>(row) + 1]; ++e) {
    const std::int32_t c = p.column[static_cast<std::size_t>(e)];
    s.insert({m.node(static_cast<std::size_t>(c / 2)), c % 2});
  }
  return s;
}

// The strip's cells, all of them and this process's run of columns, and their DofMaps on one
// process and split among the world's.
class DofOwnership : public ::testing::Test {
 protected:
  DofOwnership() {
    g.cells = {kCellsX + 4, kCellsY + 4};
    all = cell_blocks(g, 0, kCellsX);
    mine = cell_blocks(g, first_cell(r), first_cell(r + 1));
    std::vector<double> mass(g.node_count(), 0.0);
    for (std::int64_t i : all) mass[static_cast<std::size_t>(i)] = 1.0;
    const std::vector<std::uint8_t> held(g.node_count(), 0);
    one.build(all.data(), all.size() / 4, 2, 2, g, mass, held, 1);
    // This process's box: the node columns of its cells and two beyond (the mass outside it is
    // not read).
    NodeBox<2> box;
    box.lo = {std::max(0, first_cell(r) + 1 - 2), 0};
    box.hi = {std::min(g.nodes(0) - 1, first_cell(r + 1) + 1 + 2), g.nodes(1) - 1};
    boxes.set(g, box, world);
    split.build(mine.data(), mine.size() / 4, 2, 2, g, mass, held, 1, &boxes);
  }
  int first_cell(int q) const { return kCellsX * q / N; }

  const Processes world = Processes::world();
  const int N = world.size(), r = world.rank();
  GridGeometry<2> g;
  std::vector<std::int64_t> all, mine;
  BoxExchange<2> boxes;
  DofMap<2> one, split;
};

TEST_F(DofOwnership, RowsFollowThePointsBlocks) {
  ASSERT_EQ(split.global_nodes(), static_cast<long>(one.active_nodes()));
  EXPECT_TRUE(split.every_node_coupled_to_itself());
  EXPECT_EQ(split.first_node(), 0u);
  if (N > 1) {
    EXPECT_LT(split.active_nodes(), one.active_nodes()) << "a process holds every unknown";
  }

  // The runs of owned nodes' global numbers, every process's, cover the nodes in rank order.
  std::vector<double> runs(2 * static_cast<std::size_t>(N));
  const double run[2] = {static_cast<double>(split.first_global()),
                         static_cast<double>(split.first_global() + static_cast<long>(split.end_node()))};
  world.gather(run, 2, runs.data(), runs.size());
  EXPECT_EQ(runs.front(), 0.0);
  EXPECT_EQ(runs.back(), static_cast<double>(one.active_nodes()));
  for (int q = 1; q < N; ++q)
    EXPECT_EQ(runs[2 * static_cast<std::size_t>(q)], runs[2 * static_cast<std::size_t>(q) - 1]);
  const auto owner = [&](long global) {
    for (int q = 0; q < N; ++q)
      if (static_cast<double>(global) >= runs[2 * static_cast<std::size_t>(q)] &&
          static_cast<double>(global) < runs[2 * static_cast<std::size_t>(q) + 1])
        return q;
    return -1;
  };

  // Each node is owned by the lowest rank whose cells touch it (node column i touches the
  // cells i - 2 and i - 1), and within a run numbered in flat order.
  std::int64_t last = -1;
  for (std::size_t a = split.first_node(); a < split.end_node(); ++a) {
    EXPECT_GT(split.node(a), last) << "not in flat order within the run";
    last = split.node(a);
  }
  for (std::size_t a = 0; a < split.active_nodes(); ++a) {
    const int i = static_cast<int>(split.node(a) % g.nodes(0));
    const int ix = std::max(i - 2, 0);
    int expected = 0;
    while (expected + 1 < N && first_cell(expected + 1) <= ix) ++expected;
    ASSERT_EQ(owner(split.global_node(a)), expected) << "node " << split.node(a);
    EXPECT_EQ(split.active(static_cast<std::size_t>(split.node(a))), static_cast<std::int32_t>(a));
  }
  // Every process numbers a node alike: the sum of its global numbers over the processes that
  // hold it is its number times their count.
  {
    std::vector<double> number(g.node_count(), 0.0), holders(g.node_count(), 0.0);
    for (std::size_t a = 0; a < split.active_nodes(); ++a) {
      number[static_cast<std::size_t>(split.node(a))] = static_cast<double>(split.global_node(a));
      holders[static_cast<std::size_t>(split.node(a))] = 1.0;
    }
    std::vector<double> sum(number), count(holders);
    world.sum(sum.data(), sum.size());
    world.sum(count.data(), count.size());
    for (std::size_t a = 0; a < split.active_nodes(); ++a) {
      const std::size_t i = static_cast<std::size_t>(split.node(a));
      EXPECT_EQ(sum[i], number[i] * count[i]) << "node " << i << " numbered differently";
    }
  }

  // The owned rows hold every process's couplings: the one-process pattern's rows, node for node.
  for (std::size_t a = split.first_node(); a < split.end_node(); ++a)
    for (int c = 0; c < 2; ++c) {
      const int row_split = static_cast<int>(2 * a) + c;
      const int row_one = 2 * one.active(static_cast<std::size_t>(split.node(a))) + c;
      ASSERT_EQ(row_nodes(split, row_split), row_nodes(one, row_one)) << "node " << split.node(a);
    }

  // A row it does not own holds this process's couplings only, and only where its cells touch.
  std::set<std::int64_t> touched(mine.begin(), mine.end());
  for (std::size_t a = 0; a < split.active_nodes(); ++a) {
    if (a >= split.first_node() && a < split.end_node()) continue;
    const auto s = row_nodes(split, static_cast<int>(2 * a));
    if (!touched.count(split.node(a))) {
      EXPECT_TRUE(s.empty()) << "an untouched row is held: node " << split.node(a);
      continue;
    }
    for (const auto& [node, c] : s)
      EXPECT_TRUE(touched.count(node)) << "a coupling of another process's cells";
  }

  // The rows' sums (sum_rows): each process adds, per cell of its own, 1 and the cell's index to
  // each of its nodes' two rows; after the sum the rows it owns or touches hold every process's
  // parts (the count of cells at the node and the sum of their indices), the others none.
  std::vector<double> v(2 * split.active_nodes(), 0.0), expect(v.size(), 0.0);
  const auto add_cells = [&](const std::vector<std::int64_t>& blocks, std::vector<double>& to, int first) {
    for (std::size_t b = 0; b < blocks.size() / 4; ++b)
      for (int k = 0; k < 4; ++k) {
        const std::int32_t held_at = split.active(static_cast<std::size_t>(blocks[4 * b + k]));
        if (held_at < 0) continue;  // (beyond this process's box)
        const std::size_t a = static_cast<std::size_t>(held_at);
        to[2 * a] += 1.0;
        to[2 * a + 1] += static_cast<double>(first * kCellsY) + static_cast<double>(b);
      }
  };
  add_cells(mine, v, first_cell(r));
  for (int q = 0; q < N; ++q)
    add_cells(cell_blocks(g, first_cell(q), first_cell(q + 1)), expect, first_cell(q));
  split.sum_rows(v.data());
  for (std::size_t a = 0; a < split.active_nodes(); ++a) {
    const bool held_here = (a >= split.first_node() && a < split.end_node()) || touched.count(split.node(a));
    for (int c = 0; c < 2; ++c)
      EXPECT_EQ(v[2 * a + c], held_here ? expect[2 * a + c] : 0.0)
          << "node " << split.node(a) << ", row " << c;
  }

  // Not the whole matrix in every process: only a cut's layer of nodes is held twice.
  const long held_entries = world.sum_of(static_cast<long>(split.pattern().column.size()));
  const long whole = static_cast<long>(one.pattern().column.size());
  const long layer = static_cast<long>(kCellsY + 1) * 2 * 9 * 2;  // a column of nodes' rows, 9 nodes x 2 each
  EXPECT_GE(held_entries, whole);
  EXPECT_LE(held_entries, whole + (N - 1) * layer);
  if (N > 1) {
    EXPECT_LT(held_entries, N * whole);
  }
}

// A system assembled on those rows and solved on PETSc's parallel matrix: each process adds its
// cells' stiffness (a cell's Laplacian, for both components) and, in its owned rows, a unit
// mass; the solution comes back in the rows it reads (set_needed_rows: here its owned rows and
// those its cells touch) equal to the one-process solve's within the solver's round-off, and 0
// in the rows it does not read.
template <class Blocks>
std::vector<double> solve_cells(const DofMap<2>& m, const Blocks& blocks, const Processes& procs,
                                const std::vector<std::int32_t>* needed) {
  LinearSystem system;
  system.configure(LinearSolverKind::Direct, "", true, 2, procs);
  const GlobalRows rows = m.global_rows();
  system.set_pattern(m.pattern(), procs.distributed() ? &rows : nullptr);
  if (needed) system.set_needed_rows(*needed);
  std::vector<double>& v = system.values();
  for (std::size_t b = 0; b < blocks.size() / 4; ++b)
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < 4; ++l) {
        const std::size_t a = static_cast<std::size_t>(m.active(static_cast<std::size_t>(blocks[4 * b + k])));
        for (int c = 0; c < 2; ++c)
          v[static_cast<std::size_t>(m.row_entry(a, c, m.box_offset(k, l, 4)) + c)] +=
              (k == l ? 0.75 : -0.25);
      }
  for (std::size_t a = m.first_node(); a < m.end_node(); ++a)
    for (int c = 0; c < 2; ++c)
      v[static_cast<std::size_t>(m.row_entry(a, c, m.box_offset(0, 0, 4)) + c)] += 1.0;
  system.factorise();
  std::vector<double> rhs(static_cast<std::size_t>(m.dofs())), x;
  for (std::size_t a = 0; a < m.active_nodes(); ++a)  // (by node: the numberings differ)
    for (int c = 0; c < 2; ++c)
      rhs[2 * a + static_cast<std::size_t>(c)] = std::sin(0.37 * static_cast<double>(m.node(a)) + c);
  EXPECT_TRUE(system.solve(rhs, x)) << system.reason();
  return x;
}

TEST_F(DofOwnership, SolutionComesBackInTheRowsRead) {
  const std::vector<double> x_one = solve_cells(one, all, Processes{}, nullptr);
  std::vector<std::uint8_t> read(split.active_nodes(), 0);
  for (std::size_t a = split.first_node(); a < split.end_node(); ++a) read[a] = 1;
  for (std::size_t a : split.touched_not_owned()) read[a] = 1;
  std::vector<std::int32_t> needed;
  for (std::size_t a = 0; a < read.size(); ++a)
    if (read[a])
      needed.push_back(static_cast<std::int32_t>(2 * a)),
          needed.push_back(static_cast<std::int32_t>(2 * a + 1));
  const std::vector<double> x = solve_cells(split, mine, world, &needed);
  double scale = 0.0;
  for (double u : x_one) scale = std::max(scale, std::abs(u));
  ASSERT_GT(scale, 0.0);
  for (std::size_t a = 0; a < split.active_nodes(); ++a)
    for (int c = 0; c < 2; ++c) {
      const double u = x[2 * a + static_cast<std::size_t>(c)];
      if (!read[a]) {
        EXPECT_EQ(u, 0.0) << "a row this process does not read: node " << split.node(a);
        continue;
      }
      const std::size_t i =
          2 * static_cast<std::size_t>(one.active(static_cast<std::size_t>(split.node(a)))) +
          static_cast<std::size_t>(c);
      EXPECT_NEAR(u, x_one[i], 1e-12 * scale) << "node " << split.node(a) << ", component " << c;
    }
}

}  // namespace
}  // namespace skred
