// Material points stored as structure-of-arrays (one std::vector per field).
#pragma once
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/huge_pages.hpp"
#include "core/types.hpp"
#include "material/state.hpp"

namespace skred {

// Material and body ids are stored in 16 bits: a scenario has fewer of each (the scenario
// builder checks).
inline constexpr int kMaxIds = 32767;

template <int D> struct Particles {
  // Thesis §2.2: position, velocity, mass and initial volume of each material point.
  std::vector<Vec<D>> x;       // current position x_p
  std::vector<Vec<D>> x_ref;   // position at the start of the stage (displacement = x - x_ref)
  std::vector<Vec<D>> v;       // velocity v_p
  std::vector<double> mass;    // m_p
  std::vector<double> volume0; // V_p^0 (current volume V_p = det(F_p) V_p^0)
  std::vector<Vec<D>> half0;   // voxel half-lengths l_p^0 in the reference configuration
  std::vector<Mat<D>> F;       // deformation gradient F_p (Thesis eq. 3.1-3.5)
  std::vector<PointStress<D>> stress;  // Cauchy stress incl. the out-of-plane component (Voigt)
  std::vector<std::int16_t> material;  // index into the scenario's material table
  std::vector<std::int16_t> body;      // index into the scenario's body table (see kMaxBodies)
  std::vector<PointState> state;       // constitutive state (plastic strain, yield flag)
  // Elastic part of F (F = Fe Fp, Post eq. 67-74), identity at the reference state, and the
  // stress of that reference state (sigma_initial of Post eq. 77). The reference stress is
  // stored only once an initial stress is set (see set_reference_stress); empty, it is zero.
  std::vector<Mat<D>> Fe;
  std::vector<PointStress<D>> stress_ref;

  std::size_t size() const { return x.size(); }

  // Room for n points, on huge pages where the arrays are large (see huge_pages.hpp).
  void reserve(std::size_t n) {
    reserve_huge(x, n); reserve_huge(x_ref, n); reserve_huge(v, n); reserve_huge(mass, n);
    reserve_huge(volume0, n); reserve_huge(half0, n); reserve_huge(F, n); reserve_huge(stress, n);
    reserve_huge(material, n); reserve_huge(body, n); reserve_huge(state, n); reserve_huge(Fe, n);
    if (!stress_ref.empty()) reserve_huge(stress_ref, n);
  }

  // Appends one undeformed, stress-free material point.
  void add(const Vec<D>& pos, const Vec<D>& vel, double m, double vol, const Vec<D>& half,
           int mat, int bod) {
    assert(mat >= 0 && mat < kMaxIds && bod >= 0 && bod < kMaxIds);
    x.push_back(pos); x_ref.push_back(pos); v.push_back(vel); mass.push_back(m);
    volume0.push_back(vol); half0.push_back(half); F.push_back(Mat<D>::Identity());
    stress.push_back(PointStress<D>::Zero()); material.push_back(static_cast<std::int16_t>(mat));
    body.push_back(static_cast<std::int16_t>(bod));
    state.push_back(PointState{});
    Fe.push_back(Mat<D>::Identity());
    if (!stress_ref.empty()) stress_ref.push_back(PointStress<D>::Zero());
  }

  // The stress of Fe's reference state (Post eq. 77): zero unless an initial stress was set.
  PointStress<D> reference_stress(std::size_t p) const {
    return stress_ref.empty() ? PointStress<D>::Zero() : stress_ref[p];
  }
  // Makes the current stresses the reference state of Fe (after an initial stress is set).
  void set_reference_stress() { stress_ref = stress; }

  // Current volume V_p = det(F_p) V_p^0.
  double volume(std::size_t p) const { return F[p].determinant() * volume0[p]; }
};

}  // namespace skred
