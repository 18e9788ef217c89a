// Material-point splitting (Thesis §3.4.1-3.4.2). Between steps, a point whose splitting
// deformation gradient F_split meets one of the criteria of eq. 3.25 is split in two across
// the direction of the triggering mode (fig. 3.11): the children sit at x_p -+ F_p l0_k e_k / 2
// (the centres of the two halves of the deformed voxel) with half the mass, V0 and l0_k, and
// inherit F, Fe, stress and state, so they tile the parent's deformed voxel exactly; the
// triggering component of F_split is reset. A point split `reference_after` times gets the
// "reference" split of §3.4.2 instead (fig. 3.13): two square children from the deformed
// geometry with F = F_split = I and the stress carried. No point is split into children
// smaller than min_volume (scenario key min_size, a fraction of the cell: not in the thesis;
// below it the grid sees no more detail, and without it the points at a slide's front were
// split to hundreds per cell and blew up, docs/method.md "Material-point splitting"). A point
// that meets a criterion at that floor, or once the run holds max_points, gets the reference
// treatment with n = 1 instead (eq. 3.24): it stays one point, its voxel becomes the
// square of its current volume and F = F_split = I, stress carried, so its voxel cannot grow
// into a needle either.
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
  double min_volume = 0.0;                // no split into children of a smaller current volume
  std::vector<std::uint8_t> body_splits;  // per body id: 1 if its points split
  // Across processes: the points are cut into blocks again (repartition_in_blocks) once the most
  // points a process holds pass this multiple of the mean.
  double rebalance_above = 1.1;
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

// The reference treatment of §3.4.2 for point p, whose current volume V = det(F) V0 becomes
// `parts` squares (cubes): p keeps its place when parts == 1, else p and a new point sit at
// -+ `shift`. Each gets mass m / parts, V0 = V / parts, l0 = (V / parts)^(1/D) / 2 per axis,
// F = F_split = I and no splits behind it; velocity, stress and state are carried.
template <int D>
void reference_split(Particles<D>& P, std::size_t p, int parts, const Vec<D>& shift) {
  const double volume = P.F[p].determinant() * P.volume0[p] / parts;
  const Vec<D> shift_ref = P.F[p].inverse() * shift;
  const std::size_t q = parts == 2 ? P.duplicate(p) : p;
  for (std::size_t c : {p, q}) {
    const double sign = c == p ? -1.0 : 1.0;
    if (parts == 2) {
      P.x[c] += sign * shift;
      P.x_ref[c] += sign * shift_ref;
    }
    P.mass[c] /= parts;
    P.volume0[c] = volume;
    P.half0[c] = Vec<D>::Constant(0.5 * std::pow(volume, 1.0 / D));
    P.F[c] = Mat<D>::Identity();
    P.split_gauge[c] = Mat<D>::Identity();
    P.splits[c] = 0;
    if (q == p) break;
  }
}

// Splits every point of a splitting body that meets a criterion (once per call; the children
// are looked at from the next call on). Returns the number of points changed (split, or at
// the size floor or the cap reshaped into a square).
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
    // As fine as the grid sees, or no room left: reshaped, not split.
    const bool full = s.max_points > 0 && static_cast<long>(P.size()) >= s.max_points;
    if (full || 0.5 * P.F[p].determinant() * P.volume0[p] < s.min_volume) {
      reference_split<D>(P, p, 1, Vec<D>::Zero());
      ++made;
      continue;
    }
    if (P.splits[p] >= s.reference_after) {
      // Reference split (§3.4.2): across the longest deformed edge, square children with
      // F = F_split = I, each of half the current volume.
      int k = 0;
      for (int a = 1; a < D; ++a)
        if (P.F[p].col(a).norm() * P.half0[p][a] > P.F[p].col(k).norm() * P.half0[p][k]) k = a;
      reference_split<D>(P, p, 2, P.F[p].col(k) * (0.5 * P.half0[p][k]));
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
