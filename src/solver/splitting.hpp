// Material-point splitting (Thesis §3.4.1-3.4.2). Between steps, a point whose splitting
// deformation gradient F_split meets one of the criteria of eq. 3.25 is split in two across
// the direction of the triggering mode (fig. 3.11): the children sit at x_p -+ F_p l0_k e_k / 2
// (the centres of the two halves of the deformed voxel) with half the mass, V0 and l0_k, and
// inherit F, Fe, stress and state, so they tile the parent's deformed voxel exactly; the
// triggering component of F_split is reset. A point split `reference_after` times gets the
// "reference" split of §3.4.2 instead (fig. 3.13): two square children from the deformed
// geometry with F = F_split = I and the stress carried.
//
// F_split is integrated like F (eq. 3.2): both take the same increment (I + dt grad v), so
// F_split = F G with a gauge G that changes only when a split resets a mode; the particles
// store G (Particles::split_gauge) and the solver's hot loop is untouched.
//
// Eq. 3.24 as printed, l_new = (l_old / n)^(1/N_dim), is not dimensionally consistent (a
// length to the power 1/N_dim); what is implemented is the size it stands for: the child of a
// reference split is a square of the child's volume, l0 = (V_p / n)^(1/N_dim) / 2 per axis
// (half-lengths), V_p = det(F_p) V_p^0.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/particles.hpp"

namespace skred {

struct SplitSettings {
  double alpha = 2.0;                     // F_split,kk > alpha: stretched along k (eq. 3.25)
  double beta = 0.5;                      // F_split,kk < beta: squeezed along k
  double gamma = 1.0;                     // |F_split,ij| > gamma: sheared
  int reference_after = 4;                // splits after which the reference split of §3.4.2 is used
  long max_points = 0;                    // no split once the run holds this many points (0: no cap)
  std::vector<std::uint8_t> body_splits;  // per body id: 1 if its points split
};

// The mode that triggers a split and the reference axis the voxel is split across.
struct SplitMode {
  enum Kind { None, Stretch, Squeeze, Shear } kind = None;
  int i = 0, j = 0;  // the component F_split,ij (i == j for stretch and squeeze)
  int axis = 0;      // the reference axis the children are separated along
};

// The first criterion of eq. 3.25 that F_split (= F G) meets, in the order of the thesis.
template <int D>
SplitMode split_mode(const Mat<D>& Fs, const Mat<D>& F, const SplitSettings& s) {
  // A squeezed axis is split across the longest of the other deformed edges.
  const auto longest_other = [&](int k) {
    int best = k == 0 ? 1 : 0;
    for (int a = 0; a < D; ++a)
      if (a != k && F.col(a).squaredNorm() > F.col(best).squaredNorm()) best = a;
    return best;
  };
  for (int k = 0; k < D; ++k)
    if (Fs(k, k) > s.alpha) return {SplitMode::Stretch, k, k, k};
  for (int k = 0; k < D; ++k)
    if (Fs(k, k) < s.beta) return {SplitMode::Squeeze, k, k, longest_other(k)};
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j)
      if (i != j && std::abs(Fs(i, j)) > s.gamma) return {SplitMode::Shear, i, j, j};
  return {};
}

// Splits every point of a splitting body that meets a criterion (once per call; the children
// are looked at from the next call on). Returns the number of splits made.
template <int D>
long split_points(Particles<D>& P, const SplitSettings& s) {
  P.enable_splitting();
  const std::size_t n = P.size();
  long made = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const std::size_t b = static_cast<std::size_t>(P.body[p]);
    if (b >= s.body_splits.size() || !s.body_splits[b]) continue;
    const Mat<D> Fs = P.F[p] * P.split_gauge[p];
    const SplitMode mode = split_mode<D>(Fs, P.F[p], s);
    if (mode.kind == SplitMode::None) continue;
    if (s.max_points > 0 && static_cast<long>(P.size()) >= s.max_points) break;
    if (P.splits[p] >= s.reference_after) {
      // Reference split (§3.4.2): across the longest deformed edge, square children with
      // F = F_split = I, each of half the current volume.
      int k = 0;
      for (int a = 1; a < D; ++a)
        if (P.F[p].col(a).norm() * P.half0[p][a] > P.F[p].col(k).norm() * P.half0[p][k]) k = a;
      const double J = P.F[p].determinant();
      const Mat<D> F_inv = P.F[p].inverse();
      const Vec<D> shift = P.F[p].col(k) * (0.5 * P.half0[p][k]);
      const std::size_t q = P.duplicate(p);
      const double volume = 0.5 * J * P.volume0[p];
      for (std::size_t c : {p, q}) {
        const double sign = c == p ? -1.0 : 1.0;
        P.x[c] += sign * shift;
        P.x_ref[c] += sign * (F_inv * shift);
        P.mass[c] *= 0.5;
        P.volume0[c] = volume;
        P.half0[c] = Vec<D>::Constant(0.5 * std::pow(volume, 1.0 / D));
        P.F[c] = Mat<D>::Identity();
        P.split_gauge[c] = Mat<D>::Identity();
        P.splits[c] = 0;
      }
    } else {
      Mat<D> Fs_new = Fs;  // reset the triggering mode (§3.4.1)
      Fs_new(mode.i, mode.j) = mode.i == mode.j ? 1.0 : 0.0;
      const Mat<D> G = P.F[p].inverse() * Fs_new;
      const std::size_t q = P.split(p, mode.axis);
      for (std::size_t c : {p, q}) {
        P.split_gauge[c] = G;
        ++P.splits[c];
      }
    }
    ++made;
  }
  return made;
}

}  // namespace skred
