// The out-of-balance force and the matrices of an implicit iterate with Acosta's remedies
// (seed 001 §5.2-5.5; the stencils are mapped_stencils.hpp): the strain increments recovered
// with the trial functions, the internal force integrated with the test functions, the
// consistent tangent of the two, Acosta's own stiffness (eq. 5, 19-20) for iteration =
// "elastic", and the nodal magnitudes K_mag and |F_int| of eq. 25-26 for the grid frames.
#include <cmath>

#include "implicit/implicit_solver.hpp"
#include "implicit/strain_matrix.hpp"

namespace skred {

// d_eps_p = sum_b B^r_pb du_b (eq. 11, 24), the law's update, and F_int,a = V_p Bbar_pa^T W
// sigma_p (eq. 7) subtracted from r.
template <int D>
void ImplicitSolver<D>::mapped_internal_forces(const std::vector<double>& du, bool tangent, double* r) {
  using MS = MappedStencils<D>;
  const std::size_t n = state_.points.size();
  const bool axi = axisymmetric();
#pragma omp parallel for num_threads(state_.threads) schedule(static)
  for (std::size_t p = 0; p < n; ++p) {
    const std::int64_t* box = &mapped_.box[p * static_cast<std::size_t>(mapped_.KS)];
    Sym3 de = Sym3::Zero();
    for (int k = 0; k < MS::KB; ++k) {
      const int j = mapped_.trial_box[p * MS::KB + static_cast<std::size_t>(k)];
      if (j < 0) break;
      const std::int32_t a = dofs_.active(static_cast<std::size_t>(box[j]));
      if (a < 0) continue;
      const Eigen::Map<const Vec<D>> u(&du[static_cast<std::size_t>(a) * D]);
      de += strain_matrix<D>(mapped_.trial_N[p * MS::KB + static_cast<std::size_t>(k)],
                             mapped_.trial_dN[p * MS::KB + static_cast<std::size_t>(k)],
                             axi ? inv_r_[p] : 0.0) *
            u;
    }
    const Sym3 ws = mapped_.weight[p] * voigt_weighted(update_point(p, de, tangent));
    for (int k = 0; k < MS::KT; ++k) {
      const int j = mapped_.test_box[p * MS::KT + static_cast<std::size_t>(k)];
      if (j < 0) break;
      const std::int32_t a = dofs_.active(static_cast<std::size_t>(box[j]));
      if (a < 0) continue;
      const Vec<D> f = mapped_.test_B[p * MS::KT + static_cast<std::size_t>(k)].transpose() * ws;
      for (int c = 0; c < D; ++c) {
#pragma omp atomic
        r[static_cast<std::size_t>(a) * D + c] -= f[c];
      }
    }
  }
}

// Calls f(a, b, o, block) for every block of point p's stiffness: the consistent tangent
// V_p Bbar_k^T W T B^r_l, or, `acosta`, the elastic stiffness of eq. 5 (at the points: Bbar on
// both sides) or eq. 19-20 (mapped: V_p sum_g c_gp r_g B_g^T W D B_g). WT = W T (or W D).
template <int D>
template <class F>
void ImplicitSolver<D>::mapped_point_blocks(std::size_t p, const Mat6& WT, bool acosta, F&& f) const {
  using MS = MappedStencils<D>;
  const std::int64_t* box = &mapped_.box[p * static_cast<std::size_t>(mapped_.KS)];
  const auto active = [&](int j) { return dofs_.active(static_cast<std::size_t>(box[j])); };
  const double w = mapped_.weight[p];
  if (acosta && mapped_.gauss_points) {
    const bool axi = axisymmetric();
    const double h = state_.grid.h;
    for (int e = 0; e < MS::KG; ++e) {
      const int c0 = mapped_.cell_corner[p * MS::KG + static_cast<std::size_t>(e)];
      if (c0 < 0) break;
      const double r0 = mapped_.cell_r[p * MS::KG + static_cast<std::size_t>(e)];
      for (int g = 0; g < MS::KG; ++g) {
        const double c =
            mapped_.cell_c[p * MS::KG + static_cast<std::size_t>(e)][static_cast<std::size_t>(g)];
        if (c == 0.0) continue;
        const double rg = axi ? r0 + h * cell::gauss_point<D>(g)[0] : 1.0;
        std::array<StrainMatrix<D>, MS::KG> B;  // r_g B_a(x_g)
        for (int a = 0; a < MS::KG; ++a) B[static_cast<std::size_t>(a)] = MS::gauss_B(a, g, h, axi, r0);
        const Mat6 M = (w * c / rg) * WT;
        for (int b = 0; b < MS::KG; ++b) {
          const int jb = mapped_.corner_index(c0, b);
          const std::int32_t ab = active(jb);
          if (ab < 0) continue;
          const StrainMatrix<D> C = M * B[static_cast<std::size_t>(b)];
          for (int a = 0; a < MS::KG; ++a) {
            const int ja = mapped_.corner_index(c0, a);
            const std::int32_t aa = active(ja);
            if (aa < 0) continue;
            f(aa, ab, dofs_.box_offset(ja, jb, mapped_.KS),
              Mat<D>(B[static_cast<std::size_t>(a)].transpose() * C));
          }
        }
      }
    }
    return;
  }
  // Acosta's matrix at the points is symmetric (Bbar on both sides); the tangent pairs the test
  // functions with the trial ones.
  const bool own = acosta;
  const int KL = own ? MS::KT : MS::KB;
  for (int l = 0; l < KL; ++l) {
    const int jb = own ? mapped_.test_box[p * MS::KT + static_cast<std::size_t>(l)]
                       : mapped_.trial_box[p * MS::KB + static_cast<std::size_t>(l)];
    if (jb < 0) break;
    const std::int32_t ab = active(jb);
    if (ab < 0) continue;
    const StrainMatrix<D> Bl =
        own ? mapped_.test_B[p * MS::KT + static_cast<std::size_t>(l)]
            : strain_matrix<D>(mapped_.trial_N[p * MS::KB + static_cast<std::size_t>(l)],
                               mapped_.trial_dN[p * MS::KB + static_cast<std::size_t>(l)],
                               axisymmetric() ? inv_r_[p] : 0.0);
    const StrainMatrix<D> C = w * (WT * Bl);
    for (int k = 0; k < MS::KT; ++k) {
      const int ja = mapped_.test_box[p * MS::KT + static_cast<std::size_t>(k)];
      if (ja < 0) break;
      const std::int32_t aa = active(ja);
      if (aa < 0) continue;
      f(aa, ab, dofs_.box_offset(ja, jb, mapped_.KS),
        Mat<D>(mapped_.test_B[p * MS::KT + static_cast<std::size_t>(k)].transpose() * C));
    }
  }
}

template <int D>
Mat6 ImplicitSolver<D>::weighted_tangent(std::size_t p, bool elastic) const {
  Mat6 WT = elastic ? elastic_tangent_[static_cast<std::size_t>(state_.points.material[p])] : tangent_[p];
  WT.bottomRows<3>() *= 2.0;
  return WT;
}

// The stiffness of the remedies (mapped_point_blocks) with the inertia and the held rows.
template <int D>
void ImplicitSolver<D>::assemble_mapped(double dt, bool elastic) {
  std::vector<double>& values = system_.values();
  std::fill(values.begin(), values.end(), 0.0);
  double* v = values.data();
  const std::size_t n = state_.points.size();
  if (elastic && mapped_.gauss_points) {
    assemble_by_cells(v);
    add_inertia_and_held(
        dt,
        cell_pattern_ ? dofs_.box_offset(0, 0, MappedStencils<D>::KG) : dofs_.box_offset(0, 0, mapped_.KS),
        v);
    return;
  }
#pragma omp parallel for num_threads(state_.threads) schedule(static)
  for (std::size_t p = 0; p < n; ++p)
    mapped_point_blocks(p, weighted_tangent(p, elastic), elastic,
                        [&](std::int32_t a, std::int32_t b, int o, const Mat<D>& block) {
                          add_block(static_cast<std::size_t>(a), static_cast<std::size_t>(b), o, block, v);
                        });
  add_inertia_and_held(dt, dofs_.box_offset(0, 0, mapped_.KS), v);
}

// Acosta's stiffness of the mapped integrations cell by cell (App. C, fig. 32): each cell's
// Gauss points gather W D_g A_g = sum_p c_gp V_p W D_p from the points that map to them, then
// K_el = sum_g r_g B_g^T (W D_g A_g) B_g: the same sum as mapped_point_blocks' with one B^T D B
// per Gauss point instead of one per point and Gauss point.
template <int D>
void ImplicitSolver<D>::assemble_by_cells(double* v) {
  using MS = MappedStencils<D>;
  const std::size_t n = state_.points.size();
  const bool axi = axisymmetric();
  const double h = state_.grid.h;
  clear_cell_slots();
  cell_node_.clear();
  cell_r0_.clear();
  cell_D_.clear();
  for (std::size_t p = 0; p < n; ++p) {  // in point order: the sums do not depend on threads
    const std::int64_t* box = &mapped_.box[p * static_cast<std::size_t>(mapped_.KS)];
    const Mat6 WD = mapped_.weight[p] * weighted_tangent(p, true);
    for (int e = 0; e < MS::KG; ++e) {
      const int c0 = mapped_.cell_corner[p * MS::KG + static_cast<std::size_t>(e)];
      if (c0 < 0) break;
      const std::int64_t corner = box[c0];
      std::int32_t& slot = cell_slot_[static_cast<std::size_t>(corner)];
      if (slot < 0) {
        slot = static_cast<std::int32_t>(cell_node_.size());
        cell_slots_set_.push_back(corner);
        cell_node_.push_back(corner);
        cell_r0_.push_back(mapped_.cell_r[p * MS::KG + static_cast<std::size_t>(e)]);
        cell_D_.emplace_back();
        for (Mat6& m : cell_D_.back()) m.setZero();
      }
      const auto& c = mapped_.cell_c[p * MS::KG + static_cast<std::size_t>(e)];
      for (int g = 0; g < MS::KG; ++g)
        if (c[static_cast<std::size_t>(g)] != 0.0)
          cell_D_[static_cast<std::size_t>(slot)][static_cast<std::size_t>(g)] +=
              c[static_cast<std::size_t>(g)] * WD;
    }
  }
  const int cells = static_cast<int>(cell_node_.size());
  std::array<std::int64_t, MS::KG> step{};  // flat offset of corner a from corner 0
  std::array<int, MS::KG> local{};          // its index in a box of the pattern's width
  for (int a = 0; a < MS::KG; ++a) {
    for (int d = 0; d < D; ++d)
      if ((a >> d) & 1) step[static_cast<std::size_t>(a)] += static_cast<std::int64_t>(state_.grid.stride(d));
    local[static_cast<std::size_t>(a)] = cell_pattern_ ? a : mapped_.corner_index(0, a);
  }
  const int K = cell_pattern_ ? MS::KG : mapped_.KS;
#pragma omp parallel for num_threads(state_.threads) schedule(static)
  for (int k = 0; k < cells; ++k) {
    std::array<std::int32_t, MS::KG> act;
    for (int a = 0; a < MS::KG; ++a)
      act[static_cast<std::size_t>(a)] = dofs_.active(static_cast<std::size_t>(
          cell_node_[static_cast<std::size_t>(k)] + step[static_cast<std::size_t>(a)]));
    const double r0 = cell_r0_[static_cast<std::size_t>(k)];
    for (int g = 0; g < MS::KG; ++g) {
      const Mat6& M = cell_D_[static_cast<std::size_t>(k)][static_cast<std::size_t>(g)];
      const double rg = axi ? r0 + h * cell::gauss_point<D>(g)[0] : 1.0;
      std::array<StrainMatrix<D>, MS::KG> B;  // r_g B_a(x_g)
      for (int a = 0; a < MS::KG; ++a) B[static_cast<std::size_t>(a)] = MS::gauss_B(a, g, h, axi, r0);
      for (int b = 0; b < MS::KG; ++b) {
        if (act[static_cast<std::size_t>(b)] < 0) continue;
        const StrainMatrix<D> C = (M / rg) * B[static_cast<std::size_t>(b)];
        for (int a = 0; a < MS::KG; ++a) {
          if (act[static_cast<std::size_t>(a)] < 0) continue;
          add_block(
              static_cast<std::size_t>(act[static_cast<std::size_t>(a)]),
              static_cast<std::size_t>(act[static_cast<std::size_t>(b)]),
              dofs_.box_offset(local[static_cast<std::size_t>(a)], local[static_cast<std::size_t>(b)], K),
              Mat<D>(B[static_cast<std::size_t>(a)].transpose() * C), v);
        }
      }
    }
  }
}

// cell_slot_ -1 at every node: assigned once, then reset only where it was set since
// (cell_slots_set_), in O(the cells) rather than O(the grid).
template <int D>
void ImplicitSolver<D>::clear_cell_slots() {
  if (cell_slot_.size() != state_.grid.node_count())
    cell_slot_.assign(state_.grid.node_count(), -1);
  else
    for (const std::int64_t corner : cell_slots_set_) cell_slot_[static_cast<std::size_t>(corner)] = -1;
  cell_slots_set_.clear();
}

// The corner nodes of every cell a point maps to, once each (a block of 2^D per cell).
template <int D>
void ImplicitSolver<D>::mapped_cells(std::vector<std::int64_t>& blocks) {
  using MS = MappedStencils<D>;
  const std::size_t n = state_.points.size();
  clear_cell_slots();
  blocks.clear();
  for (std::size_t p = 0; p < n; ++p) {
    const std::int64_t* box = &mapped_.box[p * static_cast<std::size_t>(mapped_.KS)];
    for (int e = 0; e < MS::KG; ++e) {
      const int c0 = mapped_.cell_corner[p * MS::KG + static_cast<std::size_t>(e)];
      if (c0 < 0) break;
      const std::int64_t corner = box[c0];
      if (cell_slot_[static_cast<std::size_t>(corner)] >= 0) continue;
      cell_slot_[static_cast<std::size_t>(corner)] = 0;
      cell_slots_set_.push_back(corner);
      for (int a = 0; a < MS::KG; ++a) {
        std::int64_t f = corner;
        for (int d = 0; d < D; ++d)
          if ((a >> d) & 1) f += static_cast<std::int64_t>(state_.grid.stride(d));
        blocks.push_back(f);
      }
    }
  }
}

// K_mag = sqrt(K_x^2 + K_y^2 (+ K_z^2)) per grid node (eq. 25) from the diagonal of the elastic
// stiffness as the step's integration builds it (eq. 5 or 19-20), and |F_int| (eq. 26) of the
// last converged step; false before the first step.
template <int D>
bool ImplicitSolver<D>::node_magnitudes(std::vector<double>& k_mag, std::vector<double>& f_mag) const {
  const bool stored = !f_int_.empty() && dofs_.active_nodes() > 0;
  if (!(state_.processes.distributed() ? state_.processes.any(stored) : stored)) return false;
  const std::size_t nodes = state_.grid.node_count();
  std::vector<double> diag(static_cast<std::size_t>(dofs_.dofs()), 0.0);
  const std::size_t n = state_.points.size();
  for (std::size_t p = 0; p < n; ++p) {
    const Mat6 WT = weighted_tangent(p, true);
    const auto add = [&](std::int32_t a, std::int32_t b, int, const Mat<D>& block) {
      if (a != b) return;
      for (int c = 0; c < D; ++c) diag[static_cast<std::size_t>(a) * D + c] += block(c, c);
    };
    if (!settings_.at_points()) {
      mapped_point_blocks(p, WT, true, add);
      continue;
    }
    const int K = stencils_.K;
    for (int k = 0; k < K; ++k) {
      const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
      if (a < 0) continue;
      const StrainMatrix<D> B =
          strain_matrix<D>(stencils_.N[p * K + k], stencils_.dN[p * K + k], axisymmetric() ? inv_r_[p] : 0.0);
      add(a, a, 0, Mat<D>(volume_[p] * B.transpose() * WT * B));
    }
  }
  sum_in_boxes(diag);
  k_mag.assign(nodes, 0.0);
  f_mag.assign(nodes, 0.0);
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a) {
    const std::size_t i = static_cast<std::size_t>(dofs_.node(a));
    k_mag[i] = Eigen::Map<const Vec<D>>(&diag[a * D]).norm();
    f_mag[i] = Eigen::Map<const Vec<D>>(&f_int_[a * D]).norm();
  }
  if (state_.processes.distributed())  // the first process writes the grid's file: it gets every box's
    boxes_.gather_to_first(
        2,
        [&](std::size_t i, double* at) {
          at[0] = k_mag[i];
          at[1] = f_mag[i];
        },
        [&](std::size_t i, const double* at) {
          k_mag[i] = at[0];
          f_mag[i] = at[1];
        });
  return true;
}

template <int D>
StepStatus ImplicitSolver<D>::evaluate_at_rest() {
  if (StepStatus m = map_step(); !m.ok) return m;
  external_forces(state_.clock.time, f_ext_);
  du_.assign(static_cast<std::size_t>(dofs_.dofs()), 0.0);
  v_bar_.clear();  // no inertia
  residual(du_, dt_, false);
  store_internal_force(dt_);
  return {};
}

template <int D>
void ImplicitSolver<D>::node_internal_force(std::vector<Vec<D>>& f) const {
  f.assign(state_.grid.node_count(), Vec<D>::Zero());
  if (f_int_.empty()) return;
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
    f[static_cast<std::size_t>(dofs_.node(a))] = Eigen::Map<const Vec<D>>(&f_int_[a * D]);
}

#define SKRED_IMPLICIT_MAPPED(D)                                                                      \
  template void ImplicitSolver<D>::mapped_internal_forces(const std::vector<double>&, bool, double*); \
  template void ImplicitSolver<D>::assemble_mapped(double, bool);                                     \
  template void ImplicitSolver<D>::assemble_by_cells(double*);                                        \
  template void ImplicitSolver<D>::mapped_cells(std::vector<std::int64_t>&);                          \
  template void ImplicitSolver<D>::clear_cell_slots();                                                \
  template bool ImplicitSolver<D>::node_magnitudes(std::vector<double>&, std::vector<double>&) const; \
  template StepStatus ImplicitSolver<D>::evaluate_at_rest();                                          \
  template void ImplicitSolver<D>::node_internal_force(std::vector<Vec<D>>&) const;
SKRED_IMPLICIT_MAPPED(2)
SKRED_IMPLICIT_MAPPED(3)
#undef SKRED_IMPLICIT_MAPPED

}  // namespace skred
