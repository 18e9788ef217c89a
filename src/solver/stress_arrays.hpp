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
        mats(materials.data()),
        single(materials.size() == 1) {}

  SKRED_INLINE StressUpdateResult update(long p, const Mat<D>& grad_v, double dt) const {
    Mat<D> untracked = Mat<D>::Identity();  // Fe's update when Fe is not stored (dropped)
    return update_point_stress<D>(mats[single ? 0 : material[p]], grad_v, dt, volume0[p], stress[p], state[p],
                                  F[p], Fe ? Fe[p] : untracked);
  }
  // update() with its stored and dissipated work summed into `work` and `dissipation`, and
  // the point recorded in `bad` (the lowest so far) if it is not sound.
  SKRED_INLINE StressUpdateResult update_booked(long p, const Mat<D>& grad_v, double dt, double& work,
                                                double& dissipation, long& bad) const {
    const StressUpdateResult r = update(p, grad_v, dt);
    if (det_f) det_f[p] = F[p].determinant();
    work += r.strain_energy;
    dissipation += r.dissipation;
    if (!sound_point(r, stress[p])) bad = std::min(bad, p);
    return r;
  }
};

}  // namespace skred
