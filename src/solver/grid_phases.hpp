// The grid phases of the explicit step (Thesis eq. 2.23, 2.49, 2.52, 5.8-5.11) as functions of
// one continuum's fields: the centre-of-mass fields, or with contact one deformable body's
// (Paper III §C.2.7). Each reads and writes the fields its comment names, over the box of
// nodes the points reach (transfer/node_box.hpp); the solver (explicit_solver.hpp) calls them
// for each continuum and books what they return. A distributed run sums the mapped fields
// over the processes before them.
#pragma once
#include <vector>

#include "core/grid.hpp"
#include "solver/boundary.hpp"
#include "solver/grid_fields.hpp"
#include "transfer/box_exchange.hpp"
#include "transfer/node_box.hpp"

namespace skred {

// What the grid phases read besides the fields.
template <int D>
struct GridStep {
  const GridGeometry<D>& grid;
  NodeBox<D> box;  // the nodes the points reach
  int threads;
  const Boundaries<D>& walls;
  Vec<D> gravity;           // g now (eq. 4.13)
  double dt;                // the step
  double local_damping;     // alpha of a damped equilibrium stage; 0: off
  bool form_velocity_next;  // the velocity transfer takes v_i^{k+1} (velocity_transfer.hpp)
  // With contact, every body's fields: a node where more than one has mass is an interface
  // node, which the local damping leaves to the contact phase. Null without contact.
  const std::vector<BodyFields<D>>* bodies = nullptr;
  // Split among processes, their boxes (the walls' work counts each node once); else null.
  const BoxExchange<D>* exchange = nullptr;
};

// Eq. 2.23. Reads m_i, p_i; writes v_i = p_i / m_i under the velocity conditions.
template <int D>
void nodal_velocity(const GridStep<D>& s, GridFields<D>& f);

// USL and the averaged scheme's remap. Reads m_i, p~_i; writes v~_i = p~_i / m_i under the
// velocity conditions; clears m_i, p_i and p~_i behind, ready for the next step's map.
template <int D>
void remap_velocity(const GridStep<D>& s, GridFields<D>& f);

// Clears m_i and p_i.
template <int D>
void clear_mass_momentum(const GridStep<D>& s, GridFields<D>& f);

// Eq. 2.49 with lumped mass and eq. 2.52: a_i = (f_i^int + m_i g) / m_i (f_i^int is read from,
// and a_i written to, f.acceleration), with the local damping's share d_i where it is on; then
// v_move = v_i^k + dt/2 a_i (eq. 2.55, Post eq. 31), the walls (eq. 5.8-5.11, writing s_i), and
// v_i^{k+1} = p_i / m_i + dt a_i where the transfer takes it. Reads m_i, p_i, v_i. Returns what
// the walls took.
template <int D>
WallEnergy grid_update(const GridStep<D>& s, GridFields<D>& f);

}  // namespace skred
