// The implicit step across processes (issue 55; implicit_solver.hpp): the box of the grid each
// process holds and its scratch there, the sums between the boxes, the rows of the solution a
// process reads, and the norms and failing points agreed over the processes (one process: its
// own, with no exchange).
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "implicit/implicit_solver.hpp"
#include "transfer/node_box.hpp"

namespace skred {

// Across processes: the box of nodes this process holds. It must hold every node coupled to a
// node its points touch, since it numbers the columns of the rows it owns (dof_map.hpp). A point
// in cell c (lower node c per axis) touches nodes c - 1 .. c + 2 (the widest stencils, 4 nodes);
// a block couples nodes at most Sb - 1 apart, Sb <= 4 for the points' and the mapped stencils
// and Sp + 1 <= 5 for a cell's box with the cell-averaged strain. reach_of (node_box.hpp) spans
// c - 5 .. c + 5 of the points' extreme cells, so one layer beyond it holds c - 5 .. c + 6.
// Collective.
template <int D>
void ImplicitSolver<D>::set_box() {
  const GridGeometry<D>& g = state_.grid;
  Extent<D> e;
  for (std::size_t p = 0; p < state_.points.size(); ++p) e.add(state_.points.x[p]);
  NodeBox<D> box = reach_of(g, e);
  if (!box.empty())
    for (int d = 0; d < D; ++d) {
      box.lo[d] = std::max(0, box.lo[d] - 1);
      box.hi[d] = std::min(g.nodes(d) - 1, box.hi[d] + 1);
    }
  boxes_.set(g, box, state_.processes);
}

// Across processes: the per-node scratch sized to the grid (untouched pages) and cleared in the
// box the previous step wrote it in, so that it is clear everywhere; then that box is this
// step's. (One process assigns the whole grid as it goes.)
template <int D>
void ImplicitSolver<D>::clear_scratch() {
  const std::size_t nodes = state_.grid.node_count();
  const bool prescribed = !model_.prescribed.empty();
  grid_mass_.resize(nodes);
  grid_held_.resize(nodes);
  sliver_.resize(nodes);
  grid_prescribed_.resize(prescribed ? nodes : 0);
  grid_driven_.resize(prescribed ? nodes : 0);
  if (!scratch_box_.empty())
    for_box(state_.grid, scratch_box_, state_.threads, [&](std::size_t i) {
      grid_mass_[i] = 0.0;
      grid_held_[i] = sliver_[i] = 0;
      if (prescribed) grid_prescribed_[i] = 0, grid_driven_[i] = 0;
    });
  scratch_box_ = boxes_.own_box();
}

// Across processes: per-unknown values (D a node) summed over the processes whose boxes hold the
// node: every node of this process's box then has every process's parts. Collective.
template <int D>
void ImplicitSolver<D>::sum_in_boxes(std::vector<double>& v) const {
  if (!state_.processes.distributed()) return;
  boxes_.sum(
      D,
      [&](std::size_t i, double* at) {
        const std::int32_t a = dofs_.active(i);
        for (int c = 0; c < D; ++c) at[c] = a >= 0 ? v[static_cast<std::size_t>(a) * D + c] : 0.0;
      },
      [&](std::size_t i, const double* at) {
        if (const std::int32_t a = dofs_.active(i); a >= 0)
          std::copy_n(at, D, &v[static_cast<std::size_t>(a) * D]);
      });
}

// A point that failed on some process, named by its index over all of them in rank order, on
// every process; -1 when none did.
template <int D>
long ImplicitSolver<D>::agreed_point(long bad) const {
  const Processes& procs = state_.processes;
  if (!procs.distributed()) return bad;
  const long offset = procs.offset(static_cast<long>(state_.points.size()));
  const long first = procs.min(bad >= 0 ? offset + bad : LONG_MAX);
  return first == LONG_MAX ? -1 : first;
}

// Across processes: the rows of du this process reads, which the solves fill (the others are not
// its points'): its own, those its blocks touch, its points' stencils' and, with Acosta's remedies,
// the nodes of its points' boxes.
template <int D>
void ImplicitSolver<D>::needed_rows() {
  std::vector<std::uint8_t> read(dofs_.active_nodes(), 0);
  std::fill(read.begin() + static_cast<long>(dofs_.first_node()),
            read.begin() + static_cast<long>(dofs_.end_node()), std::uint8_t{1});
  for (std::size_t a : dofs_.touched_not_owned()) read[a] = 1;
  const auto mark = [&](const std::vector<std::int64_t>& nodes) {
    const std::int64_t count = static_cast<std::int64_t>(state_.grid.node_count());
    for (std::int64_t i : nodes)
      if (i >= 0 && i < count)
        if (const std::int32_t a = dofs_.active(static_cast<std::size_t>(i)); a >= 0)
          read[static_cast<std::size_t>(a)] = 1;
  };
  mark(stencils_.node);
  if (!settings_.at_points()) mark(mapped_.box);
  std::vector<std::int32_t> rows;
  for (std::size_t a = 0; a < read.size(); ++a)
    if (read[a])
      for (int c = 0; c < D; ++c)
        rows.push_back(static_cast<std::int32_t>(a * D + static_cast<std::size_t>(c)));
  system_.set_needed_rows(std::move(rows));
}

// The norm of per-unknown values over the processes: each sums its owned rows (where the solves'
// and the residual's values are right), then all of them add up. One process: all the rows.
template <int D>
double ImplicitSolver<D>::owned_norm(const std::vector<double>& v) const {
  double s = 0.0;
  for (std::size_t i = D * dofs_.first_node(); i < D * dofs_.end_node(); ++i) s += v[i] * v[i];
  state_.processes.sum(&s, 1);
  return std::sqrt(s);
}

#define SKRED_IMPLICIT_ACROSS(D)                                             \
  template void ImplicitSolver<D>::set_box();                                \
  template void ImplicitSolver<D>::clear_scratch();                          \
  template void ImplicitSolver<D>::sum_in_boxes(std::vector<double>&) const; \
  template long ImplicitSolver<D>::agreed_point(long) const;                 \
  template void ImplicitSolver<D>::needed_rows();                            \
  template double ImplicitSolver<D>::owned_norm(const std::vector<double>&) const;
SKRED_IMPLICIT_ACROSS(2)
SKRED_IMPLICIT_ACROSS(3)
#undef SKRED_IMPLICIT_ACROSS

}  // namespace skred
