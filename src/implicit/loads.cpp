// The external forces of an implicit step at time t (Acosta eq. 3-4): gravity on the points'
// masses, f_i = sum_p N_ip m_p g(t) (the stage's sine ramp, Thesis eq. 4.13), and the pressures
// on bodies' faces that move with the material (§3.1, fig. 2c-d), both on the step's grid.
// Axisymmetric: per radian (the masses already are; a face's area is r dA).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <unordered_map>

#include "implicit/implicit_solver.hpp"
#include "solver/gravity.hpp"

namespace skred {

template <int D>
void ImplicitSolver<D>::external_forces(double t, std::vector<double>& f) const {
  f.assign(static_cast<std::size_t>(dofs_.dofs()), 0.0);
  const Vec<D> g = gravity_at(model_.gravity, state_.clock.gravity_ramp_time, t - state_.clock.ramp_start);
  const int K = stencils_.K;
  double* fa = f.data();
  const std::size_t n = g.squaredNorm() > 0.0 ? state_.points.size() : 0;
#pragma omp parallel for num_threads(state_.threads) schedule(static)
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < K; ++k) {
      const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
      if (a < 0) continue;
      const double w = stencils_.N[p * K + k] * state_.points.mass[p];
      for (int c = 0; c < D; ++c) {
#pragma omp atomic
        fa[static_cast<std::size_t>(a) * D + c] += w * g[c];
      }
    }
  pressure_forces(t, f);
  sum_in_boxes(f);  // every process's points
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
    for (int c = 0; c < D; ++c)
      if (dofs_.held(a, c)) f[a * D + c] = 0.0;
}

// Across processes (issue 55): of each row's outermost points, one per process, only the
// outermost of all stays, the first in rank order where they tie (as one process would keep the
// first in index order); the others leave `outermost`. Every process calls it alike.
template <int D>
void ImplicitSolver<D>::keep_outermost_over_processes(
    std::unordered_map<std::int64_t, std::size_t>& outermost, int axis, bool hi) const {
  const Processes& procs = state_.processes;
  if (!procs.distributed()) return;
  std::vector<double> mine;  // (row key, coordinate) pairs; keys below 2^53 are exact doubles
  mine.reserve(2 * outermost.size());
  for (const auto& [key, p] : outermost) {
    mine.push_back(static_cast<double>(key));
    mine.push_back(state_.points.x[p][axis]);
  }
  const long start = procs.offset(static_cast<long>(mine.size()));
  std::vector<double> all(static_cast<std::size_t>(procs.sum_of(static_cast<long>(mine.size()))));
  procs.gather(mine.data(), mine.size(), all.data(), all.size());
  std::unordered_map<std::int64_t, std::size_t> best;  // row key -> its outermost entry in `all`
  for (std::size_t e = 0; e < all.size(); e += 2) {
    auto [it, fresh] = best.try_emplace(static_cast<std::int64_t>(all[e]), e);
    if (!fresh && (hi ? all[e + 1] > all[it->second + 1] : all[e + 1] < all[it->second + 1])) it->second = e;
  }
  std::erase_if(outermost, [&](const auto& row) {
    const std::size_t e = best.at(row.first);
    return e < static_cast<std::size_t>(start) || e >= static_cast<std::size_t>(start) + mine.size();
  });
}

// A pressure on the `side` face of a body: the body's points are grouped in rows across the
// face (by their position in units of their voxel size), the outermost point of each row towards
// the side carries p times its voxel's face area (axisymmetric: times the face's radius) at the
// edge of its domain, x_p -+ l_p with l_p = l_p^0 F_aa, pushing into the body. The force goes to
// the nodes with the linear (B-spline grids: the B-spline) weights at that edge point.
template <int D>
void ImplicitSolver<D>::pressure_forces(double t, std::vector<double>& f) const {
  const GridGeometry<D>& g = state_.grid;
  for (const BoundaryPressure& pr : model_.pressures) {
    const double ramp = pr.ramp_time > 0.0 ? std::min(1.0, std::max(0.0, t / pr.ramp_time)) : 1.0;
    const double value = pr.pressure * ramp;
    if (value == 0.0) continue;
    const int axis = pr.side / 2;
    const bool hi = pr.side % 2 == 1;
    std::unordered_map<std::int64_t, std::size_t> outermost;
    for (std::size_t p = 0; p < state_.points.size(); ++p) {
      if (state_.points.body[p] != pr.body) continue;
      std::int64_t key = 0;
      for (int d = 0; d < D; ++d) {
        if (d == axis) continue;
        const double cell = 2.0 * state_.points.half0[p][d];
        key = key * 4194304 +
              static_cast<std::int64_t>(std::lround((state_.points.x[p][d] - g.origin[d]) / cell - 0.5));
      }
      auto [it, fresh] = outermost.try_emplace(key, p);
      if (!fresh && (hi ? state_.points.x[p][axis] > state_.points.x[it->second][axis]
                        : state_.points.x[p][axis] < state_.points.x[it->second][axis]))
        it->second = p;
    }
    keep_outermost_over_processes(outermost, axis, hi);
    for (const auto& [key, p] : outermost) {
      Vec<D> edge = state_.points.x[p];
      edge[axis] +=
          (hi ? 1.0 : -1.0) * state_.points.half0[p][axis] * std::abs(state_.points.F[p](axis, axis));
      double area = 1.0;
      for (int d = 0; d < D; ++d)
        if (d != axis) area *= 2.0 * state_.points.half0[p][d] * std::abs(state_.points.F[p](d, d));
      if (axisymmetric()) area *= edge[0];
      Vec<D> force = Vec<D>::Zero();
      force[axis] = (hi ? -1.0 : 1.0) * value * area;
      auto spread = [&](const auto& kernel) {
        using St = typename std::decay_t<decltype(kernel)>::StencilT;
        St st;
        if (!kernel(g, edge, state_.points.half0[p], state_.points.F[p], st)) return;
        const StencilOffsets<D, St::width> offsets(g);
        for (int k = 0; k < St::size; ++k) {
          const std::int32_t a = dofs_.active(st.base + offsets.off[static_cast<std::size_t>(k)]);
          if (a < 0) continue;
          for (int c = 0; c < D; ++c)
            f[static_cast<std::size_t>(a) * D + c] += st.w[static_cast<std::size_t>(k)] * force[c];
        }
      };
      if (state_.interpolation == Interpolation::Bspline)
        spread(BsplineKernel<D>{});
      else
        spread(LinearKernel<D>{});
    }
  }
}

template void ImplicitSolver<2>::keep_outermost_over_processes(std::unordered_map<std::int64_t, std::size_t>&,
                                                               int, bool) const;
template void ImplicitSolver<3>::keep_outermost_over_processes(std::unordered_map<std::int64_t, std::size_t>&,
                                                               int, bool) const;
template void ImplicitSolver<2>::external_forces(double, std::vector<double>&) const;
template void ImplicitSolver<3>::external_forces(double, std::vector<double>&) const;
template void ImplicitSolver<2>::pressure_forces(double, std::vector<double>&) const;
template void ImplicitSolver<3>::pressure_forces(double, std::vector<double>&) const;

}  // namespace skred
