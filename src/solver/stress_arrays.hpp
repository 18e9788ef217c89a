// What the stress phases share: the per-point arrays of the stress update, the check of a
// point after it, and the blocks of points the phases take at a time.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/inline.hpp"
#include "core/particles.hpp"
#include "material/material.hpp"
#include "solver/stress_update.hpp"

namespace skred {

// After a stress update: false if the point's volume collapsed or inverted (det F <= 0) or its
// stress is not finite.
template <class V>
SKRED_INLINE bool sound_point(const StressUpdateResult& r, const V& stress) {
  return r.volume > 0.0 && std::isfinite(stress.sum());
}

// The axisymmetric update (Acosta App. A1, eq. 32): the in-plane grad v and the hoop rate v_r / r
// of the point make a 3 x 3 gradient whose third axis is the hoop direction, and the point is
// updated as a 3D point (update_point_stress<3>) with F_theta_theta = hoop; its volume per radian
// is det F hoop V0. Fe (when tracked) keeps its in-plane part. Out of line: the 2D phases take it
// in every instantiation, and inlined there the 3D update doubled their build time.
StressUpdateResult update_point_axisymmetric(const Material& mat, const Mat<2>& grad_v, double hoop_rate,
                                             double dt, double volume0, PointStress<2>& stress,
                                             PointState& state, Mat<2>& F, Mat<2>* Fe, double& hoop);

// Points per block of the stress phase: a block's gathers run first, then its material
// updates, then its scatters, so the out-of-order core overlaps the independent points' long
// update chains (docs/method.md, "The stress phase in blocks").
inline constexpr long kPointBlock = 8;

// The blocks of kPointBlock consecutive points among n: their count, and block b's points
// [first(b), last(b)).
struct PointBlocks {
  long n;
  long count() const { return (n + kPointBlock - 1) / kPointBlock; }
  long first(long b) const { return b * kPointBlock; }
  long last(long b) const { return std::min(n, first(b) + kPointBlock); }
};

// Asks for the cache lines of F, Fe and stress of the block of points from q on, which the stress
// update reads and writes, two blocks ahead of their update (docs/method.md, "Prefetches").
template <class A>
SKRED_INLINE void prefetch_block(const A& S, long q, long n) {
  if (q + kPointBlock > n) return;
  const char* f = reinterpret_cast<const char*>(S.F + q);
  const char* st = reinterpret_cast<const char*>(S.stress + q);
  for (std::size_t o = 0; o < kPointBlock * sizeof(*S.F); o += 64) __builtin_prefetch(f + o, 1);
  if (S.Fe) {
    const char* fe = reinterpret_cast<const char*>(S.Fe + q);
    for (std::size_t o = 0; o < kPointBlock * sizeof(*S.F); o += 64) __builtin_prefetch(fe + o, 1);
  }
  for (std::size_t o = 0; o < kPointBlock * sizeof(*S.stress); o += 64) __builtin_prefetch(st + o, 1);
}

// The per-point arrays the stress update reads and writes (Thesis eq. 4.1-4.4, Post 72-73),
// for the phases that update stresses.
template <int D>
struct StressArrays {
  const double* __restrict volume0;
  const std::int16_t* __restrict material;
  Mat<D>* __restrict F;
  Mat<D>* __restrict Fe;  // null when Fe is not tracked (Particles::track_elastic_F)
  PointStress<D>* __restrict stress;
  PointState* __restrict state;
  // Axisymmetric geometry (2D, x the radius): the hoop stretch F_theta_theta = r / r_0 of each
  // point (Particles::hoop); null in plane strain and 3D.
  double* __restrict hoop;
  const Material* mats;
  bool single;              // one material: the ids need not be read
  double* det_f = nullptr;  // if set, update_booked and the 3D lanes write each updated point's det F

  StressArrays(Particles<D>& P, const std::vector<Material>& materials)
      : volume0(P.volume0.data()),
        material(P.material.data()),
        F(P.F.data()),
        Fe(P.Fe.empty() ? nullptr : P.Fe.data()),
        stress(P.stress.data()),
        state(P.state.data()),
        hoop(P.hoop.empty() ? nullptr : P.hoop.data()),
        mats(materials.data()),
        single(materials.size() == 1) {}

  SKRED_INLINE StressUpdateResult update(long p, const Mat<D>& grad_v, double dt) const {
    Mat<D> untracked = Mat<D>::Identity();  // Fe's update when Fe is not stored (dropped)
    return update_point_stress<D>(mats[single ? 0 : material[p]], grad_v, dt, volume0[p], stress[p], state[p],
                                  F[p], Fe ? Fe[p] : untracked);
  }
  // The axisymmetric update (axisymmetric_update.cpp).
  SKRED_INLINE StressUpdateResult update_axisymmetric(long p, const Mat<D>& grad_v, double hoop_rate,
                                                      double dt) const {
    static_assert(D == 2, "axisymmetric geometry is 2D");
    return update_point_axisymmetric(mats[single ? 0 : material[p]], grad_v, hoop_rate, dt, volume0[p],
                                     stress[p], state[p], F[p], Fe ? Fe + p : nullptr, hoop[p]);
  }
  // update() or, where hoop_rate is given (axisymmetric), update_axisymmetric(), with its stored
  // and dissipated work booked as update_booked does.
  SKRED_INLINE StressUpdateResult update_booked(long p, const Mat<D>& grad_v, double hoop_rate, double dt,
                                                double& work, double& dissipation, long& bad) const {
    if constexpr (D == 2)
      if (hoop) {
        const StressUpdateResult r = update_axisymmetric(p, grad_v, hoop_rate, dt);
        return book(p, r, work, dissipation, bad);
      }
    return update_booked(p, grad_v, dt, work, dissipation, bad);
  }
  // update() with its stored and dissipated work summed into `work` and `dissipation`, and
  // the point recorded in `bad` (the lowest so far) if it is not sound.
  SKRED_INLINE StressUpdateResult update_booked(long p, const Mat<D>& grad_v, double dt, double& work,
                                                double& dissipation, long& bad) const {
    return book(p, update(p, grad_v, dt), work, dissipation, bad);
  }
  SKRED_INLINE StressUpdateResult book(long p, const StressUpdateResult& r, double& work, double& dissipation,
                                       long& bad) const {
    if (det_f) det_f[p] = F[p].determinant();
    work += r.strain_energy;
    dissipation += r.dissipation;
    if (!sound_point(r, stress[p])) bad = std::min(bad, p);
    return r;
  }
};

}  // namespace skred
