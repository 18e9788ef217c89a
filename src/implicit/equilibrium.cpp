// The out-of-balance force of an implicit iterate and its tangent (implicit_solver.hpp; Acosta
// eq. 4-6, 10-11, 47): each point's strain increment and law update, the internal force, and
// the stiffness matrix, with the cell-averaged volumetric strain when it is on (cell_boxes.hpp).
#include <algorithm>
#include <array>
#include <cmath>

#include "implicit/implicit_solver.hpp"
#include "implicit/strain_matrix.hpp"
#include "material/law.hpp"

namespace skred {

// Point p's strain increment d_eps = sum_i B_i du_i (eq. 5, 11).
template <int D>
Sym3 ImplicitSolver<D>::point_strain(std::size_t p, const std::vector<double>& du) const {
  const int K = stencils_.K;
  const double inv_r = axisymmetric() ? inv_r_[p] : 0.0;
  Sym3 de = Sym3::Zero();
  for (int k = 0; k < K; ++k) {
    const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
    if (a < 0) continue;
    const Eigen::Map<const Vec<D>> u(&du[static_cast<std::size_t>(a) * D]);
    de += strain_matrix<D>(stencils_.N[p * K + k], stencils_.dN[p * K + k], inv_r) * u;
  }
  return de;
}

// The law's update of point p for the strain increment de (eq. 6), kept as the trial state.
template <int D>
const Sym3& ImplicitSolver<D>::update_point(std::size_t p, const Sym3& de, bool tangent) {
  const Material& mat = state_.materials[static_cast<std::size_t>(state_.points.material[p])];
  LawResult res = evaluate(mat, full_stress<D>(state_.points.stress[p]), de, state_.points.state[p], tangent);
  deps_[p] = de;
  trial_stress_[p] = res.stress;
  trial_plastic_[p] = res.plastic_strain;
  trial_state_[p] = res.state;
  if (tangent) tangent_[p] = res.tangent;
  return trial_stress_[p];
}

// Subtracts point p's internal force V B_i^T (W sigma) (eq. 4) from r on its nodes; ws = V W sigma.
template <int D>
void ImplicitSolver<D>::subtract_internal_force(std::size_t p, const Sym3& ws, double* r) const {
  const int K = stencils_.K;
  const double inv_r = axisymmetric() ? inv_r_[p] : 0.0;
  for (int k = 0; k < K; ++k) {
    const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
    if (a < 0) continue;
    const Vec<D> f =
        strain_matrix<D>(stencils_.N[p * K + k], stencils_.dN[p * K + k], inv_r).transpose() * ws;
    for (int c = 0; c < D; ++c) {
#pragma omp atomic
      r[static_cast<std::size_t>(a) * D + c] -= f[c];
    }
  }
}

// The points' strain increments and the laws' update at the iterate du (eq. 5-6), then
// R = F_ext - F_int - M (4 du / dt^2 - 4 v / dt - a) (eq. 47; without the last term when
// quasi-static or `inertia` is false), zero on held components (their values kept as the
// supports' forces, held_force_). Returns |R|.
//
// With the cell-averaged volumetric strain (cell_boxes.hpp) a point's increment takes its
// cell's volume-weighted mean volumetric part, d_eps_p + (theta_c - theta_p) / d m, and its
// internal force pairs with it through the cell's mean pressure: sigma_p + (q_c - q_p) m,
// q = m^T sigma / d (the explicit engine's solver/volumetric_averaging.hpp).
template <int D>
double ImplicitSolver<D>::residual(const std::vector<double>& du, double dt, bool tangent) {
  const std::size_t n = state_.points.size();
  deps_.resize(n);
  trial_stress_.resize(n);
  trial_plastic_.resize(n);
  trial_state_.resize(n);
  if (tangent) tangent_.resize(n);
  // Across processes each sums its own points' internal forces, and the rows' owners the whole
  // of their rows, which they send back to the processes that touch them (DofMap::sum_rows): R
  // is right in those rows, and |R| is summed over the owned rows.
  const bool split = state_.processes.distributed();
  if (split)
    r_.assign(f_ext_.size(), 0.0);
  else
    r_ = f_ext_;
  double* r = r_.data();
  timer_.time(ImplicitPhase::StressUpdate, [&] {
    if (!settings_.at_points()) {
      mapped_internal_forces(du, tangent, r);
      return;
    }
    if (!averaging()) {
#pragma omp parallel for num_threads(state_.threads) schedule(static)
      for (std::size_t p = 0; p < n; ++p) {
        const Sym3& s = update_point(p, point_strain(p, du), tangent);
        subtract_internal_force(p, volume_[p] * voigt_weighted(s), r);
      }
      return;
    }
    // Three passes, each cell's sums over the processes between them: theta_c, then the laws
    // and q_c, then the forces.
    const Sym3 m = volumetric_axes();
    const double d = m.sum();
    vol_corr_.resize(n);
    mean_.resize(n);
    const int cells = cells_.cells();
    cell_theta_.assign(static_cast<std::size_t>(cells), 0.0);
    cell_mean_.assign(static_cast<std::size_t>(cells), 0.0);
#pragma omp parallel for num_threads(state_.threads) schedule(dynamic, 64)
    for (int c = 0; c < cells; ++c) {
      double theta = 0.0;
      for (int q = cells_.start[c]; q < cells_.start[c + 1]; ++q) {
        const std::size_t p = static_cast<std::size_t>(cells_.points[q]);
        deps_[p] = point_strain(p, du);
        theta += volume_[p] * m.dot(deps_[p]);
      }
      cell_theta_[static_cast<std::size_t>(c)] = theta;
    }
    cells_.sum_cells(cell_theta_.data(), 1);
#pragma omp parallel for num_threads(state_.threads) schedule(dynamic, 64)
    for (int c = 0; c < cells; ++c) {
      const double theta =
          cell_theta_[static_cast<std::size_t>(c)] / cells_.volume[static_cast<std::size_t>(c)];
      double mean = 0.0;
      for (int q = cells_.start[c]; q < cells_.start[c + 1]; ++q) {
        const std::size_t p = static_cast<std::size_t>(cells_.points[q]);
        vol_corr_[p] = (theta - m.dot(deps_[p])) / d;
        const Sym3& s = update_point(p, Sym3(deps_[p] + vol_corr_[p] * m), tangent);
        mean_[p] = m.dot(s) / d;
        mean += volume_[p] * mean_[p];
      }
      cell_mean_[static_cast<std::size_t>(c)] = mean;
    }
    cells_.sum_cells(cell_mean_.data(), 1);
#pragma omp parallel for num_threads(state_.threads) schedule(dynamic, 64)
    for (int c = 0; c < cells; ++c) {
      const double mean =
          cell_mean_[static_cast<std::size_t>(c)] / cells_.volume[static_cast<std::size_t>(c)];
      for (int q = cells_.start[c]; q < cells_.start[c + 1]; ++q) {
        const std::size_t p = static_cast<std::size_t>(cells_.points[q]);
        subtract_internal_force(p, volume_[p] * (voigt_weighted(trial_stress_[p]) + (mean - mean_[p]) * m),
                                r);
      }
    }
  });
  if (split) {
    dofs_.sum_rows(r);
    for (std::size_t i = 0; i < r_.size(); ++i) r_[i] += f_ext_[i];
  }
  const bool inertia = dynamic() && !v_bar_.empty();
  const double c0 = 4.0 / (dt * dt), c1 = 4.0 / dt;
  double s = 0.0;
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
    for (int c = 0; c < D; ++c) {
      const std::size_t i = a * D + c;
      if (inertia) r_[i] -= mass_[i] * (c0 * du[i] - c1 * v_bar_[i] - a_bar_[i]);  // eq. 9-10, 47
      if (dofs_.held(a, c)) {
        held_force_[i] = -r_[i];
        r_[i] = 0.0;
        continue;
      }
      if (a >= dofs_.first_node() && a < dofs_.end_node()) s += r_[i] * r_[i];
    }
  state_.processes.sum(&s, 1);
  return std::sqrt(s);
}

// Adds the block sum_kl Bk^T WT Bl of point p (its stencil's pairs) to the matrix values v;
// with `project`, Bk is the deviatoric part P Bk = Bk - m m^T Bk / d (the cell-averaged
// volumetric strain), and g, h (the box's K entries, by the point's box indices) gain
// Bk^T WT m / d and Bk^T WT^T m / d.
template <int D>
void ImplicitSolver<D>::add_point_block(std::size_t p, const Mat6& WT, bool project, Vec<D>* g, Vec<D>* h,
                                        double* v) const {
  const int K = stencils_.K;
  const double inv_r = axisymmetric() ? inv_r_[p] : 0.0;
  const Sym3 m = volumetric_axes();
  const double d = m.sum();
  std::array<StrainMatrix<D>, kMaxStencil> B;
  for (int k = 0; k < K; ++k) {
    B[static_cast<std::size_t>(k)] = strain_matrix<D>(stencils_.N[p * K + k], stencils_.dN[p * K + k], inv_r);
    if (project) {
      StrainMatrix<D>& Bk = B[static_cast<std::size_t>(k)];
      const Eigen::Matrix<double, 1, D> div = m.transpose() * Bk;
      Bk -= m * div / d;
      const int j = cells_.local[p * K + k];
      g[j] += Bk.transpose() * (WT * m) / d;
      h[j] += Bk.transpose() * (WT.transpose() * m) / d;
    }
  }
  for (int l = 0; l < K; ++l) {
    const std::int32_t b = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + l]));
    if (b < 0) continue;
    const StrainMatrix<D> C = WT * B[static_cast<std::size_t>(l)];
    for (int k = 0; k < K; ++k) {
      const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
      if (a < 0) continue;
      const Mat<D> block = B[static_cast<std::size_t>(k)].transpose() * C;
      add_block(static_cast<std::size_t>(a), static_cast<std::size_t>(b), dofs_.pair_offset(k, l, K), block,
                v);
    }
  }
}

// Adds a D x D block coupling active nodes a and b (b at offset o from a) to the values v,
// leaving out held rows and columns.
template <int D>
void ImplicitSolver<D>::add_block(std::size_t a, std::size_t b, int o, const Mat<D>& block, double* v) const {
  for (int r = 0; r < D; ++r) {
    if (dofs_.held(a, r)) continue;
    const std::int32_t e = dofs_.row_entry(a, r, o);
    for (int c = 0; c < D; ++c) {
      if (dofs_.held(b, c)) continue;
#pragma omp atomic
      v[e + c] += block(r, c);
    }
  }
}

// K = sum_p V B_i^T W T B_j (eq. 5, 10-11; T the laws' consistent tangent at the iterate, or
// the elastic matrix for Acosta's iteration) + 4 M / dt^2 (eq. 10, dynamic), held rows and
// columns replaced by the identity. With the cell-averaged volumetric strain a point's B is
// P B + m b_c / d (cell_boxes.hpp), and its K splits into the point's own block P B^T WT P B and
// the cell's g b_c^T + b_c h^T + s b_c b_c^T, s = sum V m^T W T m / d^2, over the cell's box.
template <int D>
void ImplicitSolver<D>::assemble(double dt, bool elastic) {
  std::vector<double>& values = system_.values();
  std::fill(values.begin(), values.end(), 0.0);
  double* v = values.data();
  if (!settings_.at_points()) {
    assemble_mapped(dt, elastic);
    return;
  }
  const std::size_t n = state_.points.size();
  const auto point_WT = [&](std::size_t p) {
    Mat6 WT = elastic ? elastic_tangent_[static_cast<std::size_t>(state_.points.material[p])] : tangent_[p];
    WT.bottomRows<3>() *= 2.0;
    return Mat6(volume_[p] * WT);
  };
  if (!averaging()) {
#pragma omp parallel for num_threads(state_.threads) schedule(static)
    for (std::size_t p = 0; p < n; ++p) add_point_block(p, point_WT(p), false, nullptr, nullptr, v);
  } else {
    const Sym3 m = volumetric_axes();
    const double d = m.sum();
    const int cells = cells_.cells(), Kc = cells_.K;
#pragma omp parallel for num_threads(state_.threads) schedule(dynamic, 64)
    for (int c = 0; c < cells; ++c) {
      std::array<Vec<D>, kMaxBox> g, h;
      std::fill_n(g.begin(), Kc, Vec<D>::Zero());
      std::fill_n(h.begin(), Kc, Vec<D>::Zero());
      double s = 0.0;
      for (int q = cells_.start[c]; q < cells_.start[c + 1]; ++q) {
        const std::size_t p = static_cast<std::size_t>(cells_.points[q]);
        const Mat6 WT = point_WT(p);
        add_point_block(p, WT, true, g.data(), h.data(), v);
        s += m.dot(WT * m) / (d * d);
      }
      if (cells_.start[c] == cells_.start[c + 1]) continue;  // (another process's cell)
      const std::int64_t* box = &cells_.node[static_cast<std::size_t>(c) * Kc];
      const Vec<D>* b = &cells_.mean_div[static_cast<std::size_t>(c) * Kc];
      for (int i = 0; i < Kc; ++i) {
        const std::int32_t ai = dofs_.active(static_cast<std::size_t>(box[i]));
        if (ai < 0) continue;
        for (int j = 0; j < Kc; ++j) {
          const std::int32_t aj = dofs_.active(static_cast<std::size_t>(box[j]));
          if (aj < 0) continue;
          const Mat<D> block = g[i] * b[j].transpose() + b[i] * (h[j] + s * b[j]).transpose();
          add_block(static_cast<std::size_t>(ai), static_cast<std::size_t>(aj), dofs_.box_offset(i, j, Kc),
                    block, v);
        }
      }
    }
  }
  add_inertia_and_held(dt, dofs_.pair_offset(0, 0, stencils_.K), v);
}

// The diagonal's 4 m_i / dt^2 (eq. 10, dynamic) and the held rows' identity; `centre` is a
// node's offset to itself in the pattern. Across processes, each adds them to its own rows.
template <int D>
void ImplicitSolver<D>::add_inertia_and_held(double dt, int centre, double* v) const {
  const double c0 = dynamic() ? 4.0 / (dt * dt) : 0.0;
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
    for (int r = 0; r < D; ++r) {
      if (!system_.owns(a * D + static_cast<std::size_t>(r))) continue;
      const std::int32_t e = dofs_.row_entry(a, r, centre) + r;
      v[e] += dofs_.held(a, r) ? 1.0 : c0 * mass_[a * D + r];
    }
}

#define SKRED_IMPLICIT_EQUILIBRIUM(D)                                                    \
  template double ImplicitSolver<D>::residual(const std::vector<double>&, double, bool); \
  template void ImplicitSolver<D>::assemble(double, bool);                               \
  template void ImplicitSolver<D>::add_inertia_and_held(double, int, double*) const;
SKRED_IMPLICIT_EQUILIBRIUM(2)
SKRED_IMPLICIT_EQUILIBRIUM(3)
#undef SKRED_IMPLICIT_EQUILIBRIUM

}  // namespace skred
