// Nodal fields of the background grid, stored as structure-of-arrays. Each array holds one
// quantity for the whole step, named as in the seeds (subscript i: node).
#pragma once
#include <cstddef>
#include <vector>

#include "core/huge_pages.hpp"
#include "core/types.hpp"

namespace skred {

template <int D>
struct GridFields {
  GridArray<double> mass;      // m_i = sum N_ip m_p (Thesis eq. 2.53)
  GridArray<Vec<D>> momentum;  // p_i = sum N_ip m_p v_p (eq. 2.54)
  GridArray<Vec<D>> velocity;  // v_i^k = p_i / m_i under the velocity conditions (eq. 2.23)
  // First f_i^int = -sum sigma_p V_p grad N_ip (eq. 2.51), summed by the stress phase; the grid
  // update turns it in place into a_i = (f_i^int + f_i^ext) / m_i (eq. 2.49, 2.52), with
  // f_i^ext = m_i g; after the boundary conditions (v_i^{k+1} - p_i / m_i) / dt, the velocity
  // change handed to the particles (eq. 2.56), so that they obey the walls too. (One array for
  // both: nothing reads the force once the acceleration is formed.)
  GridArray<Vec<D>> acceleration;
  GridArray<Vec<D>> velocity_move;  // (v_i^k + v_i^{k+1}) / 2: moves the points (eq. 2.55)
  // s_i, the part of a_i with which the walls stop a node: at the boundary nodes every component
  // at a fixed wall and the normal one at a roller or frictional wall, zero elsewhere; for the
  // walls' share of the lumped mass's loss (WallEnergy).
  GridArray<Vec<D>> stopped_acceleration;
  // v_i^{k+1} = p_i / m_i + dt a_i, for the PIC share of the particle velocity update and
  // APIC; for XPIC(m), v_i^{k+1} - p_i / m_i + v*_i (allocated only when the transfer uses it).
  GridArray<Vec<D>> velocity_next;
  // XPIC(m): a scratch array (allocated only for XPIC; v*_i is formed in velocity_next).
  GridArray<Vec<D>> xpic_work;
  // The momentum remap of USL and the averaged scheme (Thesis §4.4 step 6; not Acosta's
  // double mapping of stresses, eq. 12-13): the updated
  // particle momenta mapped back, p~_i = sum N_ip m_p v_p^{k+1}, and v~_i = p~_i / m_i, which
  // the second stress update reads (allocated only for those schemes).
  GridArray<Vec<D>> momentum_remap;
  GridArray<Vec<D>> velocity_remap;
  // d_i = f_i^damp / m_i, the local damping's share of a_i in an equilibrium stage that damps
  // (grid_update, grid_phases.hpp; allocated at the first damped step).
  GridArray<Vec<D>> damping_acceleration;

  // n zero nodes (fresh pages: see GridArray). Call once, on empty fields.
  void resize(std::size_t n, bool pic, bool remap, bool xpic = false) {
    for (auto* f : {&momentum, &velocity, &acceleration, &velocity_move, &stopped_acceleration}) f->resize(n);
    mass.resize(n);
    if (pic || xpic) velocity_next.resize(n);
    if (xpic) xpic_work.resize(n);
    if (remap) {
      momentum_remap.resize(n);
      velocity_remap.resize(n);
    }
  }
  std::size_t size() const { return mass.size(); }
};

// The fields of one body (continuum) on the grid, beside the centre-of-mass fields above:
// what multi-continuum contact (Paper III §C.2.7) works on. Without contact only m_i^b and
// p_i^b are allocated; with contact every array, each with the meaning above for body b
// alone (f_i^int,b, a_i^b after contact, ...).
template <int D>
struct BodyFields : GridFields<D> {
  // With contact: the change the contact made to v_i^k,b (contact.cpp), which the strain and
  // the motion take but the points' velocities do not (they take only accelerations).
  GridArray<Vec<D>> velocity_shift;
  // With a pair under the traction rule (ContactDetection::Traction): S_i^b = sum_p N_ip m_p
  // sigma_p of the body's points, its diagonal and off-diagonal parts (traction_at), mapped at
  // the start of the step (map_body_stress); allocated only then.
  GridArray<Vec<D>> stress_diagonal, stress_off;
};

}  // namespace skred
