// What both integrators do with the shared state between steps (mpm_state.hpp): the particle
// totals, the start of a stage, the restore of a checkpoint and the grid-smoothed stresses.
#include "solver/mpm_state.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "shape/separable.hpp"
#include "transfer/box_exchange.hpp"
#include "transfer/node_box.hpp"

namespace skred {

namespace {

// a <- n entries `z` (zero): a mapped array is mapped afresh, so that no page is touched
// (core/huge_pages.hpp), a small one written.
template <class T>
void zero(GridArray<T>& a, std::size_t n, const T& z) {
  if (a.size() != n || n * sizeof(T) >= ZeroPageAllocator<T>::kMappedBytes) {
    GridArray<T>().swap(a);
    a.resize(n);
  } else {
    std::fill(a.begin(), a.end(), z);
  }
}

// The smoothing's sums over the processes (Thesis eq. 4.18's sums over every point): each process
// over the box its points reach (transfer/box_exchange.hpp), and the first one, which writes the
// grid's file, over the whole grid.
template <int D>
void sum_smoothing_over_processes(const GridGeometry<D>& g, const Particles<D>& P, const Processes& procs,
                                  NodalSmoothing<D>& s) {
  static_assert(sizeof(Sym3) == 6 * sizeof(double) && sizeof(Vec<D>) == D * sizeof(double));
  Extent<D> e;
  for (std::size_t p = 0; p < P.size(); ++p) e.add(P.x[p]);
  BoxExchange<D> boxes;
  boxes.set(g, reach_of(g, e), procs);
  constexpr int per = 1 + 6 + D;
  const auto pack = [&](std::size_t i, double* at) {
    at[0] = s.mass[i];
    for (int c = 0; c < 6; ++c) at[1 + c] = s.stress[i].data()[c];
    for (int d = 0; d < D; ++d) at[7 + d] = s.velocity[i][d];
  };
  const auto set = [&](std::size_t i, const double* at) {
    s.mass[i] = at[0];
    for (int c = 0; c < 6; ++c) s.stress[i].data()[c] = at[1 + c];
    for (int d = 0; d < D; ++d) s.velocity[i][d] = at[7 + d];
  };
  boxes.sum(per, pack, set);
  boxes.gather_to_first(per, pack, set);
}

}  // namespace

template <int D>
MpmState<D>::MpmState(Particles<D>& points_, GridGeometry<D> grid_, Interpolation interpolation_,
                      int quadrature_points_, std::vector<Material> materials_, int threads_)
    : points(points_),
      grid(grid_),
      interpolation(interpolation_),
      quadrature_points(quadrature_points_),
      materials(std::move(materials_)),
      threads(std::max(1, threads_)) {
  grid.bspline_dofs = interpolation == Interpolation::Bspline;
  for (Material& m : materials) m.prepare();
}

template <int D>
ParticleTotals<D> particle_totals(const Particles<D>& P, int threads, const Processes& processes) {
  const long n = static_cast<long>(P.size());
  double mass = 0.0, ke = 0.0, speed_mass = 0.0, vmax = 0.0;
  long yielding = 0;
  Vec<D> mom = Vec<D>::Zero();
#pragma omp parallel for num_threads(threads) reduction(+ : mass, ke, speed_mass, yielding) \
    reduction(max : vmax) reduction(vsum : mom)
  for (long p = 0; p < n; ++p) {
    const double m = P.mass[p], s = P.v[p].norm();
    mass += m;
    ke += 0.5 * m * s * s;  // eq. 4.15
    speed_mass += m * s;    // eq. 5.12
    vmax = std::max(vmax, s);
    mom += m * P.v[p];
    yielding += P.state[p].yielding;
  }
  if (processes.distributed()) {  // every process's points
    double sums[4 + D] = {mass, ke, speed_mass, static_cast<double>(yielding)};
    for (int d = 0; d < D; ++d) sums[4 + d] = mom[d];
    processes.sum(sums, 4 + D);
    mass = sums[0], ke = sums[1], speed_mass = sums[2], yielding = static_cast<long>(sums[3]);
    for (int d = 0; d < D; ++d) mom[d] = sums[4 + d];
    processes.max(&vmax, 1);
  }
  ParticleTotals<D> t;
  t.mass = mass;
  t.kinetic_energy = ke;
  t.momentum = mom;
  t.mean_speed = mass > 0.0 ? speed_mass / mass : 0.0;
  t.max_speed = vmax;
  t.yielding = yielding;
  return t;
}

template <int D>
void restore(MpmState<D>& state, const SolverClock& clock, std::vector<Material> materials) {
  state.materials = std::move(materials);
  for (Material& m : state.materials) m.prepare();
  state.clock = clock;
}

template <int D>
void begin_stage(MpmState<D>& state, std::vector<Material> materials, double gravity_ramp_time) {
  SolverClock c = state.clock;
  c.ramp_start = c.time;
  c.gravity_ramp_time = gravity_ramp_time;
  c.energy = EnergyTotals{};
  restore(state, c, std::move(materials));
  Particles<D>& P = state.points;
  P.x_ref = P.x;
  for (std::size_t p = 0; p < P.size(); ++p) {
    P.state[p].volume_strain = std::log(P.F[p].determinant());
    P.state[p].yielding = 0;
  }
}

// Thesis eq. 4.18: sigma_i = sum sigma_p N_ip m_p / m_i; eq. 4.19: sigma_p = sum sigma_i N_ip.
template <int D>
void smoothed_stress(MpmState<D>& state, std::vector<Sym3>& out) {
  with_kernel<D>(state.interpolation, state.quadrature_points, [&](const auto& kernel) {
    using K = std::decay_t<decltype(kernel)>;
    const GridGeometry<D>& g = state.grid;
    const NodeStrides<D> strides(g);
    const Particles<D>& P = state.points;
    NodalSmoothing<D>& s = state.smoothing;
    const long n = static_cast<long>(P.size());
    const std::size_t nodes = g.node_count();
    zero(s.mass, nodes, 0.0);
    zero(s.velocity, nodes, Vec<D>::Zero().eval());
    zero(s.stress, nodes, Sym3::Zero().eval());
    for (long p = 0; p < n; ++p) {  // serial scatter: run only when results are written
      typename K::Shape sh;
      if (!kernel.shape(g, P.x[p], P.half0[p], P.F[p], sh)) continue;
      const double m = P.mass[p];
      for_each_node(sh, strides, [&](std::size_t i, double w, const Vec<D>&) {
        s.mass[i] += w * m;
        s.stress[i] += (w * m) * full_stress<D>(P.stress[p]);
        s.velocity[i] += (w * m) * P.v[p];
      });
    }
    if (const Processes& procs = state.processes; procs.distributed() && nodes > 0)
      sum_smoothing_over_processes(g, P, procs, s);  // all points' sums, over each box
    for (std::size_t i = 0; i < nodes; ++i)
      if (s.mass[i] > 0.0) {
        s.stress[i] /= s.mass[i];
        s.velocity[i] /= s.mass[i];
      }
    out.resize(P.size());
#pragma omp parallel for num_threads(state.threads) schedule(static)
    for (long p = 0; p < n; ++p) {
      typename K::Shape sh;
      Sym3 acc = Sym3::Zero();
      if (kernel.shape(g, P.x[p], P.half0[p], P.F[p], sh))
        for_each_node(sh, strides, [&](std::size_t i, double w, const Vec<D>&) { acc += w * s.stress[i]; });
      out[p] = acc;
    }
  });
}

#define SKRED_MPM_STATE(D)                                                                \
  template struct MpmState<D>;                                                            \
  template ParticleTotals<D> particle_totals(const Particles<D>&, int, const Processes&); \
  template void restore(MpmState<D>&, const SolverClock&, std::vector<Material>);         \
  template void begin_stage(MpmState<D>&, std::vector<Material>, double);                 \
  template void smoothed_stress(MpmState<D>&, std::vector<Sym3>&);
SKRED_MPM_STATE(2)
SKRED_MPM_STATE(3)
#undef SKRED_MPM_STATE

}  // namespace skred
