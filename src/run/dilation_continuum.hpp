// The dilation cut-off as a new continuum (Paper III §C.3.2): between steps, a point of a
// body with a dilated continuum whose volume strain has reached the cut-off,
// eps_v >= ln((1 + e_max) / (1 + e0)) (the test by which the Mohr-Coulomb return sets psi =
// 0, MohrCoulombConstants::max_volume_strain), joins that continuum for good. Only its body
// id changes: its mass, velocity and stress stay, so the points' mass and momentum are the
// same before and after; the solver maps each body's fields afresh (particles_changed()).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/particles.hpp"
#include "scenario/scenario.hpp"

namespace skred {

class DilationContinua {
 public:
  template <int D>
  explicit DilationContinua(const ScenarioOf<D>& s) {
    for (std::size_t d = 0; d < s.bodies.size(); ++d) {
      const int parent = s.bodies[d].dilated_from;
      if (parent < 0) continue;
      const Material& m =
          s.materials[static_cast<std::size_t>(s.bodies[static_cast<std::size_t>(parent)].material)];
      if (target_.size() <= static_cast<std::size_t>(parent))
        target_.resize(static_cast<std::size_t>(parent) + 1, -1);
      target_[static_cast<std::size_t>(parent)] = static_cast<int>(d);
      limit_.resize(target_.size(), 0.0);
      limit_[static_cast<std::size_t>(parent)] = MohrCoulombConstants(m.mohr_coulomb).max_volume_strain;
      dilated_.resize(s.bodies.size(), 0);
      dilated_[d] = 1;
    }
  }

  bool empty() const { return target_.empty(); }
  // True for the id of a dilated continuum.
  bool is_dilated(int body) const {
    return body >= 0 && static_cast<std::size_t>(body) < dilated_.size() &&
           dilated_[static_cast<std::size_t>(body)];
  }

  // Moves the points that reached the cut-off, on `threads` threads (the solver's); returns
  // how many moved (then the solver must map the grid afresh: particles_changed()).
  template <int D>
  long apply(Particles<D>& P, int threads = 1) const {
    long moved = 0;
    const long n = static_cast<long>(P.size());
#pragma omp parallel for num_threads(threads) schedule(static) reduction(+ : moved)
    for (long i = 0; i < n; ++i) {
      const auto p = static_cast<std::size_t>(i);
      const auto b = static_cast<std::size_t>(P.body[p]);
      if (b >= target_.size() || target_[b] < 0) continue;
      if (!(P.state[p].volume_strain >= limit_[b])) continue;
      P.body[p] = static_cast<std::int16_t>(target_[b]);
      ++moved;
    }
    return moved;
  }

  // The points in the dilated continua.
  template <int D>
  long count(const Particles<D>& P) const {
    long k = 0;
    for (std::size_t p = 0; p < P.size(); ++p) k += is_dilated(P.body[p]) ? 1 : 0;
    return k;
  }

 private:
  std::vector<int> target_;    // per body id: its dilated continuum, or -1
  std::vector<double> limit_;  // per body id: the volume strain of the cut-off
  std::vector<char> dilated_;  // per body id: 1 for a dilated continuum
};

}  // namespace skred
