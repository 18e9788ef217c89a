// The stencils of an implicit step with Acosta's remedies (seed 001 §5.2-5.5, App. C): for each
// point, how it integrates the internal force and stiffness (its test functions) and how its
// strain increment is recovered (its trial functions).
//
//   F_int,a = V_p Bbar_pa^T W sigma_p                      (eq. 7, 30 with Bbar)
//   d_eps_p = sum_b B^r_pb du_b                             (eq. 11, 24)
//   K_ab    = V_p Bbar_pa^T W T_p B^r_pb                    (the consistent tangent of the two)
//
// At the points (regular MPM, GIMP) Bbar = B(x_p) and V_p is the point's volume; with W* (eq.
// 15) V_p = h^D / cmp, the cell's volume shared by the points it holds. With the Gauss mapping
// the points' stresses reach the Gauss points g of the cells through the cells' nodes,
// sigma_g A_g = sum_p c_gp V_p sigma_p, c_gp = sum_a N_a(x_g) H_a(x_p) (eq. 16-18), so that
// Bbar_pa = sum_g c_gp r_g B_a(x_g) and V_p the point's area (r_g = 1 in plane strain): GM with
// H = N, DM with H = N and W*, DM-G with H = S_ip*, the local GIMP functions of every cell the
// support domain overlaps (eq. 20). Acosta's own stiffness (eq. 19-20), the iteration matrix of
// iteration = "elastic" and the K_mag of eq. 25, keeps the Gauss points apart:
// K = sum_p V_p sum_g c_gp r_g B_g^T W D_p B_g.
//
// Every node a point touches lies in its box, the 4^D nodes from its cell's lower corner - 1:
// the stiffness pattern (dof_map.hpp) is built from these boxes.
//
// Across processes (issue 55) each process builds its own points' stencils; cmp (W*, DM) counts
// every process's points, CMPM's patches follow the grid's masses (every process's), and the
// boxes are trimmed to the width the widest point of any process needs, so that all of them
// build the same pattern.
#pragma once
#include <omp.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/grid.hpp"
#include "core/particles.hpp"
#include "implicit/cell_functions.hpp"
#include "implicit/point_stencils.hpp"
#include "implicit/strain_matrix.hpp"
#include "parallel/processes.hpp"
#include "shape/gimp.hpp"
#include "solver/implicit_settings.hpp"
#include "transfer/box_exchange.hpp"

namespace skred {

template <int D>
struct MappedStencils {
  static constexpr int kWidth = 4;             // box nodes per axis
  static constexpr int KB = D == 3 ? 64 : 16;  // box nodes
  static constexpr int KT = D == 3 ? 27 : 9;   // test nodes per point (3 per axis at most)
  static constexpr int KG = cell::corners(D);  // Gauss points (and corners) per cell
  // After build() the boxes are trimmed to the width S the points need (2 for DM at the points'
  // kernel, 3 for DM-G, 4 with CMPM's cubic patches): box holds KS = S^D nodes per point and
  // every box index below counts in it.
  int width = kWidth, KS = KB;
  // Whether the internal force and Acosta's stiffness are integrated at the cells' Gauss points
  // (GM, DM, DM-G), whether or not this process holds points.
  bool gauss_points = false;
  std::vector<std::int64_t> box;               // p KS + j: flat node index of box node j
  std::vector<double> weight;                  // V_p of the integration
  std::vector<std::int8_t> test_box;           // p KT + k: box index of test node k (-1: none)
  std::vector<StrainMatrix<D>> test_B;         // its Bbar
  std::vector<std::int8_t> trial_box;          // p KB + k: box index of trial node k (-1: none)
  std::vector<double> trial_N;                 // its N (the hoop strain's u_r / r)
  std::vector<Vec<D>> trial_dN;                // and gradient
  std::vector<std::int8_t> cell_corner;        // p KG + e: box index of a mapped cell's corner 0
  std::vector<std::array<double, KG>> cell_c;  // its c_gp
  std::vector<double> cell_r;                  // its lower radial coordinate (axisymmetric)

  // The box index of node offsets o (per axis, 0..3).
  static int box_index(const std::array<int, D>& o) {
    int j = 0;
    for (int d = D - 1; d >= 0; --d) j = j * kWidth + o[static_cast<std::size_t>(d)];
    return j;
  }
  // Box index of corner a of the cell whose corner 0 has box index c0.
  int corner_index(int c0, int a) const {
    int j = c0, step = 1;
    for (int d = 0; d < D; ++d, step *= width) j += ((a >> d) & 1) * step;
    return j;
  }
  // B of corner a at Gauss point g of a cell, times r_g (axisymmetric: r0 its lower radius).
  static StrainMatrix<D> gauss_B(int a, int g, double h, bool axi, double r0) {
    const Vec<D> t = cell::gauss_point<D>(g);
    const double N = cell::corner_weight<D>(a, t);
    const Vec<D> dN = cell::corner_gradient<D>(a, t, h);
    if (!axi) return strain_matrix<D>(N, dN, 0.0);
    const double r = r0 + h * t[0];
    return r * strain_matrix<D>(N, dN, 1.0 / r);
  }

  // Builds every point's stencils. `kernel` holds the run's kernel at the points (their
  // integration at the points and their recovery at the points), `volume` V_p (per radian when
  // axisymmetric, with inv_r = 1 / r_p, else empty), `mass` per grid node (> 0: an unknown).
  // Returns a point whose stencil leaves its box, or -1; when no process has one, trim() must
  // follow. Across processes, collective over `boxes` (set: the cells' point counts, summed
  // between the processes whose boxes hold a cell's lower corner).
  long build(ForceIntegration integration, StressRecovery recovery, const PointStencils<D>& kernel,
             const GridGeometry<D>& g, const Particles<D>& P, const std::vector<double>& volume,
             const std::vector<double>& inv_r, std::span<const double> mass, int threads,
             BoxExchange<D>* boxes = nullptr) {
    const std::size_t n = P.size();
    const bool axi = !inv_r.empty();
    if (integration == ForceIntegration::ModifiedWeights || integration == ForceIntegration::DoubleMapping)
      count_points(g, P, boxes);
    width = kWidth;
    KS = KB;
    box.resize(n * KB);
    weight.resize(n);
    test_box.assign(n * KT, -1);
    test_B.resize(n * KT);
    trial_box.assign(n * KB, -1);
    trial_N.resize(n * KB);
    trial_dN.resize(n * KB);
    gauss_points = integration == ForceIntegration::GaussMapping ||
                   integration == ForceIntegration::DoubleMapping ||
                   integration == ForceIntegration::DoubleMappingGimp;
    cell_corner.assign(gauss_points ? n * KG : 0, -1);
    cell_c.resize(gauss_points ? n * KG : 0);
    cell_r.resize(gauss_points ? n * KG : 0);
    long bad = LONG_MAX;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(min : bad)
    for (std::size_t p = 0; p < n; ++p) {
      const std::array<int, D> c = cell_of(g, P.x[p]);
      std::size_t base = 0;
      for (int d = 0; d < D; ++d) base += static_cast<std::size_t>(c[d] - 1) * g.stride(d);
      for (int j = 0; j < KB; ++j) {
        std::size_t f = base;
        for (int d = 0, r = j; d < D; ++d, r /= kWidth)
          f += static_cast<std::size_t>(r % kWidth) * g.stride(d);
        box[p * KB + j] = static_cast<std::int64_t>(f);
      }
      const double r_p = axi ? 1.0 / inv_r[p] : 1.0;
      const double cell_volume = std::pow(g.h, D);
      bool ok = true;
      switch (integration) {
        case ForceIntegration::Points:
        case ForceIntegration::ModifiedWeights:
          weight[p] = integration == ForceIntegration::Points ? volume[p] : cell_volume / cmp(g, c) * r_p;
          ok = kernel_test(p, kernel, g, axi ? inv_r[p] : 0.0);
          break;
        default:
          weight[p] =
              integration == ForceIntegration::DoubleMapping ? cell_volume / cmp(g, c) : volume[p] / r_p;
          map_to_gauss_points(p, integration, c, g, P, axi);
      }
      if (recovery == StressRecovery::Points)
        ok = ok && kernel_trial(p, kernel, g);
      else
        cmpm_trial(p, c, g, P.x[p], mass);
      if (!ok) bad = std::min(bad, static_cast<long>(p));
    }
    return bad == LONG_MAX ? -1 : bad;
  }

  // Trims every point's box of 4^D nodes to the S^D around the nodes it uses, S the widest any
  // point of any process needs: the stiffness pattern couples no more nodes than the stencils do.
  // Collective over `procs`.
  void trim(const GridGeometry<D>& g, int threads, const Processes& procs) {
    const std::size_t n = weight.size();
    const bool mapped = gauss_points;
    const auto offsets = [](int j) {
      std::array<int, D> o{};
      for (int d = 0; d < D; ++d, j /= kWidth) o[static_cast<std::size_t>(d)] = j % kWidth;
      return o;
    };
    // The used range of each point per axis, from its test, trial and mapped cells' nodes.
    const auto each_used = [&](std::size_t p, auto&& f) {
      for (int k = 0; k < KT && test_box[p * KT + static_cast<std::size_t>(k)] >= 0; ++k)
        f(test_box[p * KT + static_cast<std::size_t>(k)]);
      for (int k = 0; k < KB && trial_box[p * KB + static_cast<std::size_t>(k)] >= 0; ++k)
        f(trial_box[p * KB + static_cast<std::size_t>(k)]);
      if (mapped)
        for (int e = 0; e < KG && cell_corner[p * KG + static_cast<std::size_t>(e)] >= 0; ++e) {
          const int c0 = cell_corner[p * KG + static_cast<std::size_t>(e)];
          f(c0);
          int far = c0;
          for (int d = 0, step = 1; d < D; ++d, step *= kWidth) far += step;
          f(far);
        }
    };
    std::vector<std::array<int, D>> low(n);
    int S = 2;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : S)
    for (std::size_t p = 0; p < n; ++p) {
      std::array<int, D> lo, hi{};
      lo.fill(kWidth);
      each_used(p, [&](int j) {
        const auto o = offsets(j);
        for (int d = 0; d < D; ++d) {
          lo[static_cast<std::size_t>(d)] =
              std::min(lo[static_cast<std::size_t>(d)], o[static_cast<std::size_t>(d)]);
          hi[static_cast<std::size_t>(d)] =
              std::max(hi[static_cast<std::size_t>(d)], o[static_cast<std::size_t>(d)]);
        }
      });
      for (int d = 0; d < D; ++d)
        S = std::max(S, hi[static_cast<std::size_t>(d)] - lo[static_cast<std::size_t>(d)] + 1);
      low[p] = lo;
    }
    S = static_cast<int>(procs.max(static_cast<long>(S)));
    width = S;
    KS = 1;
    for (int d = 0; d < D; ++d) KS *= S;
    std::vector<std::int64_t> trimmed(n * static_cast<std::size_t>(KS));
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::size_t p = 0; p < n; ++p) {
      std::array<int, D> shift{};
      for (int d = 0; d < D; ++d)
        shift[static_cast<std::size_t>(d)] = std::min(low[p][static_cast<std::size_t>(d)], kWidth - S);
      const auto remap = [&](int j) {
        const auto o = offsets(j);
        int r = 0;
        for (int d = D - 1; d >= 0; --d)
          r = r * S + o[static_cast<std::size_t>(d)] - shift[static_cast<std::size_t>(d)];
        return static_cast<std::int8_t>(r);
      };
      for (int k = 0; k < KT && test_box[p * KT + static_cast<std::size_t>(k)] >= 0; ++k)
        test_box[p * KT + static_cast<std::size_t>(k)] =
            remap(test_box[p * KT + static_cast<std::size_t>(k)]);
      for (int k = 0; k < KB && trial_box[p * KB + static_cast<std::size_t>(k)] >= 0; ++k)
        trial_box[p * KB + static_cast<std::size_t>(k)] =
            remap(trial_box[p * KB + static_cast<std::size_t>(k)]);
      if (mapped)
        for (int e = 0; e < KG && cell_corner[p * KG + static_cast<std::size_t>(e)] >= 0; ++e)
          cell_corner[p * KG + static_cast<std::size_t>(e)] =
              remap(cell_corner[p * KG + static_cast<std::size_t>(e)]);
      for (int j = 0; j < KS; ++j) {
        std::size_t f = static_cast<std::size_t>(box[p * KB]);
        for (int d = 0, r = j; d < D; ++d, r /= S)
          f += static_cast<std::size_t>(shift[static_cast<std::size_t>(d)] + r % S) * g.stride(d);
        trimmed[p * static_cast<std::size_t>(KS) + static_cast<std::size_t>(j)] =
            static_cast<std::int64_t>(f);
      }
    }
    box.swap(trimmed);
  }

 private:
  // The cell holding x (its lower corner's node index per axis), a point on an upper wall in
  // the last cell.
  static std::array<int, D> cell_of(const GridGeometry<D>& g, const Vec<D>& x) {
    std::array<int, D> c{};
    for (int d = 0; d < D; ++d) {
      const int j = static_cast<int>(std::floor((x[d] - g.origin[d]) / g.h)) + GridGeometry<D>::pad;
      c[static_cast<std::size_t>(d)] = std::clamp(j, GridGeometry<D>::pad, g.cells[d]);
    }
    return c;
  }
  static std::size_t cell_key(const GridGeometry<D>& g, const std::array<int, D>& c) {
    std::size_t k = 0;
    for (int d = 0; d < D; ++d) k += static_cast<std::size_t>(c[static_cast<std::size_t>(d)]) * g.stride(d);
    return k;
  }
  // cmp: the points each cell holds (keyed by its lower corner), every process's.
  void count_points(const GridGeometry<D>& g, const Particles<D>& P, BoxExchange<D>* boxes) {
    count_.assign(g.node_count(), 0);
    for (std::size_t p = 0; p < P.size(); ++p) ++count_[cell_key(g, cell_of(g, P.x[p]))];
    if (boxes && boxes->processes().distributed())
      boxes->sum(
          1, [&](std::size_t i, double* at) { at[0] = static_cast<double>(count_[i]); },
          [&](std::size_t i, const double* at) { count_[i] = static_cast<long>(at[0]); });
  }
  double cmp(const GridGeometry<D>& g, const std::array<int, D>& c) const {
    return static_cast<double>(count_[cell_key(g, c)]);
  }
  // Box index of flat node f of a box whose first node is base, -1 outside it.
  static int index_in_box(const GridGeometry<D>& g, std::int64_t base, std::int64_t f) {
    const auto b = g.unflatten(static_cast<std::size_t>(base)), q = g.unflatten(static_cast<std::size_t>(f));
    std::array<int, D> o{};
    for (int d = 0; d < D; ++d) {
      o[static_cast<std::size_t>(d)] = q[static_cast<std::size_t>(d)] - b[static_cast<std::size_t>(d)];
      if (o[static_cast<std::size_t>(d)] < 0 || o[static_cast<std::size_t>(d)] >= kWidth) return -1;
    }
    return box_index(o);
  }

  // Integration at the points: the kernel's B(x_p) (eq. 5, 7).
  bool kernel_test(std::size_t p, const PointStencils<D>& st, const GridGeometry<D>& g, double inv_r) {
    const int K = st.K;
    if (K > KT) return false;
    for (int k = 0; k < K; ++k) {
      const int j = index_in_box(g, box[p * KB], st.node[p * K + k]);
      if (j < 0) return false;
      test_box[p * KT + k] = static_cast<std::int8_t>(j);
      test_B[p * KT + k] = strain_matrix<D>(st.N[p * K + k], st.dN[p * K + k], inv_r);
    }
    return true;
  }
  // Recovery at the points: the kernel's N and gradients.
  bool kernel_trial(std::size_t p, const PointStencils<D>& st, const GridGeometry<D>& g) {
    const int K = st.K;
    for (int k = 0; k < K; ++k) {
      const int j = index_in_box(g, box[p * KB], st.node[p * K + k]);
      if (j < 0) return false;
      trial_box[p * KB + k] = static_cast<std::int8_t>(j);
      trial_N[p * KB + k] = st.N[p * K + k];
      trial_dN[p * KB + k] = st.dN[p * K + k];
    }
    return true;
  }

  // GM, DM, DM-G (eq. 16-20): the cells the point maps to, their c_gp, and Bbar.
  void map_to_gauss_points(std::size_t p, ForceIntegration integration, const std::array<int, D>& c,
                           const GridGeometry<D>& g, const Particles<D>& P, bool axi) {
    Vec<D> t;  // the point in its cell's coordinates
    for (int d = 0; d < D; ++d)
      t[d] = (P.x[p][d] - g.origin[d]) / g.h - (c[static_cast<std::size_t>(d)] - GridGeometry<D>::pad);
    // Per axis the cells of the map (offsets -1, 0, +1 from the point's) and the point's two
    // functions in each: N (GM, DM: its own cell only) or S* (DM-G: every cell its support overlaps).
    std::array<std::array<int, 2>, D> off{};
    std::array<std::array<std::array<double, 2>, 2>, D> H{};
    std::array<int, D> count{};
    Vec<D> l = Vec<D>::Zero();
    if (integration == ForceIntegration::DoubleMappingGimp) {
      const auto size = GimpKernel<D>{}.size(g, P.half0[p], P.F[p]);
      for (int d = 0; d < D; ++d) l[d] = size.lam[d];
    }
    for (int d = 0; d < D; ++d) {
      int m = 0;
      for (int o = -1; o <= 1; ++o) {
        std::array<double, 2> h{};
        if (integration == ForceIntegration::DoubleMappingGimp) {
          h = cell::local_gimp(t[d] - o, l[d]);
          if (h[0] + h[1] <= 0.0) continue;
        } else {
          if (o != 0) continue;
          h = {1.0 - t[d], t[d]};
        }
        off[static_cast<std::size_t>(d)][static_cast<std::size_t>(m)] = o;
        H[static_cast<std::size_t>(d)][static_cast<std::size_t>(m++)] = h;
      }
      count[static_cast<std::size_t>(d)] = m;
    }
    std::array<StrainMatrix<D>, KB> B;
    std::array<bool, KB> used{};
    int cells = 1;
    for (int d = 0; d < D; ++d) cells *= count[static_cast<std::size_t>(d)];
    for (int e = 0; e < cells; ++e) {
      std::array<int, D> corner0{};
      std::array<int, D> which{};
      double r0 = 0.0;
      for (int d = 0, r = e; d < D; ++d) {
        which[static_cast<std::size_t>(d)] = r % count[static_cast<std::size_t>(d)];
        r /= count[static_cast<std::size_t>(d)];
        corner0[static_cast<std::size_t>(d)] =
            1 +
            off[static_cast<std::size_t>(d)][static_cast<std::size_t>(which[static_cast<std::size_t>(d)])];
      }
      if (axi) r0 = g.origin[0] + g.node_coordinate(0, c[0] + off[0][static_cast<std::size_t>(which[0])]);
      // c_gp = sum_a N_a(x_g) H_a(x_p) (eq. 18, 20).
      std::array<double, KG> cg{};
      for (int a = 0; a < KG; ++a) {
        double Ha = 1.0;
        for (int d = 0; d < D; ++d)
          Ha *= H[static_cast<std::size_t>(d)][static_cast<std::size_t>(which[static_cast<std::size_t>(d)])]
                 [static_cast<std::size_t>((a >> d) & 1)];
        if (Ha == 0.0) continue;
        for (int q = 0; q < KG; ++q)
          cg[static_cast<std::size_t>(q)] += cell::corner_weight<D>(a, cell::gauss_point<D>(q)) * Ha;
      }
      const int c0 = box_index(corner0);
      cell_corner[p * KG + static_cast<std::size_t>(e)] = static_cast<std::int8_t>(c0);
      cell_c[p * KG + static_cast<std::size_t>(e)] = cg;
      cell_r[p * KG + static_cast<std::size_t>(e)] = r0;
      for (int a = 0; a < KG; ++a) {
        const int j = corner_index(c0, a);
        if (!used[static_cast<std::size_t>(j)]) B[static_cast<std::size_t>(j)].setZero();
        used[static_cast<std::size_t>(j)] = true;
        for (int q = 0; q < KG; ++q)
          B[static_cast<std::size_t>(j)] += cg[static_cast<std::size_t>(q)] * gauss_B(a, q, g.h, axi, r0);
      }
    }
    int k = 0;
    for (int j = 0; j < KB; ++j)
      if (used[static_cast<std::size_t>(j)]) {
        test_box[p * KT + static_cast<std::size_t>(k)] = static_cast<std::int8_t>(j);
        test_B[p * KT + static_cast<std::size_t>(k++)] = B[static_cast<std::size_t>(j)];
      }
  }

  // CMPM (eq. 21-24, fig. 33): per axis the Lagrange functions over the cell's two nodes and the
  // far node of each neighbouring cell whose nodes are all unknowns (cubic inside the body,
  // quadratic at its boundary, linear in a layer one cell thick). A node that carries mass is
  // thus in the patch of the points next to it: the tangent has no empty column.
  void cmpm_trial(std::size_t p, const std::array<int, D>& c, const GridGeometry<D>& g, const Vec<D>& x,
                  std::span<const double> mass) {
    // Per axis: extend to a side when the far nodes of that neighbour, across the cell's own
    // nodes along the other axes, all carry mass.
    const auto active = [&](const std::array<int, D>& node) {
      std::size_t f = 0;
      for (int d = 0; d < D; ++d) {
        if (node[static_cast<std::size_t>(d)] < 0 || node[static_cast<std::size_t>(d)] >= g.nodes(d))
          return false;
        f += static_cast<std::size_t>(node[static_cast<std::size_t>(d)]) * g.stride(d);
      }
      return mass[f] > 0.0;
    };
    std::array<int, D> lo{}, hi{};
    const std::array<int, D> none{};
    for (int d = 0; d < D; ++d)
      for (int side = 0; side < 2; ++side) {
        bool all = true;
        for_patch(c, none, none, [&](std::array<int, D> node, int) {
          if (((node[static_cast<std::size_t>(d)] - c[static_cast<std::size_t>(d)]) == 1) != (side == 1))
            return;
          node[static_cast<std::size_t>(d)] += side ? 1 : -1;
          all = all && active(node);
        });
        (side ? hi : lo)[static_cast<std::size_t>(d)] = all;
      }
    // A corner of two extensions without mass (a re-entrant corner of the body) drops the
    // extension of the later axis.
    for (bool changed = true; changed;) {
      changed = false;
      for_patch(c, lo, hi, [&](const std::array<int, D>& node, int) {
        if (changed || active(node)) return;
        for (int d = D - 1; d >= 0 && !changed; --d) {
          const int o = node[static_cast<std::size_t>(d)] - c[static_cast<std::size_t>(d)];
          if (o == -1) lo[static_cast<std::size_t>(d)] = 0, changed = true;
          if (o == 2) hi[static_cast<std::size_t>(d)] = 0, changed = true;
        }
      });
    }
    std::array<cell::Lagrange1D, D> L;
    for (int d = 0; d < D; ++d) {
      double xs[4];
      int m = 0;
      for (int o = -lo[static_cast<std::size_t>(d)]; o <= 1 + hi[static_cast<std::size_t>(d)]; ++o)
        xs[m++] = g.origin[d] + g.node_coordinate(d, c[static_cast<std::size_t>(d)] + o);
      L[static_cast<std::size_t>(d)] = cell::lagrange(xs, m, x[d]);
    }
    int k = 0;
    for_patch(c, lo, hi, [&](const std::array<int, D>& node, int) {
      std::array<int, D> o{};
      double N = 1.0;
      Vec<D> dN = Vec<D>::Ones();
      for (int d = 0; d < D; ++d) {
        o[static_cast<std::size_t>(d)] =
            node[static_cast<std::size_t>(d)] - c[static_cast<std::size_t>(d)] + 1;
        const std::size_t i =
            static_cast<std::size_t>(o[static_cast<std::size_t>(d)] - 1 + lo[static_cast<std::size_t>(d)]);
        const double v = L[static_cast<std::size_t>(d)].value[i], s = L[static_cast<std::size_t>(d)].slope[i];
        for (int e = 0; e < D; ++e) dN[e] *= e == d ? s : v;
        N *= v;
      }
      trial_box[p * KB + static_cast<std::size_t>(k)] = static_cast<std::int8_t>(box_index(o));
      trial_N[p * KB + static_cast<std::size_t>(k)] = N;
      trial_dN[p * KB + static_cast<std::size_t>(k++)] = dN;
    });
  }
  // f(node, k) over the patch's nodes (cell c, extended by lo / hi per axis), axis 0 fastest.
  template <class F>
  static void for_patch(const std::array<int, D>& c, const std::array<int, D>& lo,
                        const std::array<int, D>& hi, F&& f) {
    std::array<int, D> w{};
    int total = 1;
    for (int d = 0; d < D; ++d) {
      w[static_cast<std::size_t>(d)] = 2 + lo[static_cast<std::size_t>(d)] + hi[static_cast<std::size_t>(d)];
      total *= w[static_cast<std::size_t>(d)];
    }
    for (int k = 0; k < total; ++k) {
      std::array<int, D> node{};
      for (int d = 0, r = k; d < D; ++d) {
        node[static_cast<std::size_t>(d)] = c[static_cast<std::size_t>(d)] - lo[static_cast<std::size_t>(d)] +
                                            r % w[static_cast<std::size_t>(d)];
        r /= w[static_cast<std::size_t>(d)];
      }
      f(node, k);
    }
  }

  std::vector<long> count_;  // per cell (keyed by its lower corner): the points it holds (W*, DM)
};

}  // namespace skred
