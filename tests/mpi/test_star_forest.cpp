// The star forest of shared grid nodes (parallel/star_forest.hpp), under mpirun: a row of nodes
// in which each process holds a run that overlaps its neighbours'. After a reduction and a
// broadcast every holder of a node must have the sum of all its holders' values, which here is
// known in closed form (integers, so exact), and the bytes counted must be those sent.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "parallel/processes.hpp"
#include "parallel/star_forest.hpp"

namespace skred {
namespace {

// Process r holds nodes [10 r, 10 r + 14] of a row of 10 k + 5 nodes: each overlaps the next
// one's first five.
constexpr long kStride = 10, kWidth = 15;

TEST(StarForest, SumsEveryHolderOfASharedNode) {
  const Processes procs = Processes::world();
  const int r = procs.rank(), k = procs.size();
  const long first = kStride * r, nodes = kStride * k + (kWidth - kStride);
  // The lowest holder owns a node: this process owns all it holds but the first five (r > 0).
  std::vector<long> roots, leaves;
  for (long i = first; i < first + kWidth; ++i) {
    const bool shared_below = r > 0 && i < first + (kWidth - kStride);
    const bool shared_above = r + 1 < k && i >= first + kStride;
    if (shared_below)
      leaves.push_back(i);
    else if (shared_above)
      roots.push_back(i);
  }
  StarForest forest;
  forest.match_nodes(procs, nodes, roots, leaves);

  // Two values a node: process r's part is (r + 1) and (r + 1) i.
  const auto part = [&](long i, double* at) { at[0] = r + 1.0, at[1] = (r + 1.0) * static_cast<double>(i); };
  std::vector<double> root(2 * roots.size()), leaf(2 * leaves.size());
  for (std::size_t n = 0; n < roots.size(); ++n) part(roots[n], root.data() + 2 * n);
  for (std::size_t n = 0; n < leaves.size(); ++n) part(leaves[n], leaf.data() + 2 * n);
  const Exchanged before = exchanged();
  forest.reduce(2, leaf.data(), root.data());
  forest.broadcast(2, root.data(), leaf.data());
  const Exchanged after = exchanged();

  // A node shared by processes r and r + 1 sums to (r + 1) + (r + 2).
  for (std::size_t n = 0; n < roots.size(); ++n) {
    EXPECT_EQ(root[2 * n], 2.0 * r + 3.0) << "root " << roots[n];
    EXPECT_EQ(root[2 * n + 1], (2.0 * r + 3.0) * static_cast<double>(roots[n]));
  }
  for (std::size_t n = 0; n < leaves.size(); ++n) {
    EXPECT_EQ(leaf[2 * n], 2.0 * r + 1.0) << "leaf " << leaves[n];
    EXPECT_EQ(leaf[2 * n + 1], (2.0 * r + 1.0) * static_cast<double>(leaves[n]));
  }
  // Sent: its leaves (reduction) and its roots' copies (broadcast), 16 bytes a node; one message
  // to each neighbour that takes part.
  EXPECT_EQ(after.calls - before.calls, 2);
  EXPECT_DOUBLE_EQ(after.bytes - before.bytes, 16.0 * static_cast<double>(leaves.size() + roots.size()));
  EXPECT_EQ(after.messages - before.messages, (r > 0 ? 1 : 0) + (r + 1 < k ? 1 : 0));
}

// A leaf whose node no process owns is refused on the process that holds it.
TEST(StarForest, RefusesALeafWithoutAnOwner) {
  const Processes procs = Processes::world();
  const long nodes = 100;
  std::vector<long> roots, leaves{99};  // every process holds node 99; none owns it
  StarForest forest;
  EXPECT_THROW(forest.match_nodes(procs, nodes, roots, leaves), std::runtime_error);
}

// Process q holds 4 records; process r takes from each process q its records q + r and q + r + 1
// (mod 4), in rank order, as point migration does (point_shares.hpp, move_points).
TEST(StarForest, MovesRecordsToWhereTheyWereSent) {
  const Processes procs = Processes::world();
  const int r = procs.rank(), k = procs.size();
  struct Record {
    std::int64_t from;
    double value[3];
    std::uint8_t flag;
  };
  std::vector<Record> held(4);
  for (int j = 0; j < 4; ++j)
    held[static_cast<std::size_t>(j)] = {r, {r + 0.5, j * 1.0, -1.0}, static_cast<std::uint8_t>(j)};
  std::vector<int> rank;
  std::vector<long> index;
  for (int q = 0; q < k; ++q)
    for (int j = 0; j < 2; ++j) rank.push_back(q), index.push_back((q + r + j) % 4);
  StarForest forest;
  forest.connect(procs, 4, rank, index);
  std::vector<Record> taken(rank.size());
  const Exchanged before = exchanged();
  forest.broadcast_bytes(sizeof(Record), held.data(), taken.data());
  const Exchanged after = exchanged();
  for (std::size_t n = 0; n < taken.size(); ++n) {
    EXPECT_EQ(taken[n].from, rank[n]) << "slot " << n;
    EXPECT_EQ(taken[n].value[0], rank[n] + 0.5);
    EXPECT_EQ(taken[n].value[1], static_cast<double>(index[n]));
    EXPECT_EQ(taken[n].flag, index[n]);
  }
  // Each process sends two records to every other.
  EXPECT_EQ(after.messages - before.messages, k - 1);
  EXPECT_DOUBLE_EQ(after.bytes - before.bytes, 2.0 * (k - 1) * sizeof(Record));
}

}  // namespace
}  // namespace skred
