// The scenario's choices as the integrators take them: the explicit solver's settings, the
// implicit integrator's model, the grid and each stage's time or load step.

#include <algorithm>

#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "scenario/estimate.hpp"

namespace skred {

template <int D>
SolverSettings<D> solver_settings(const ScenarioOf<D>& s) {
  SolverSettings<D> st;
  st.interpolation = s.interpolation;
  st.quadrature_points = s.quadrature_points;
  st.scheme = s.scheme;
  st.dt = scenario_time_step(s);
  st.gravity = s.gravity;
  st.gravity_ramp_time = s.gravity_ramp_time;
  st.boundaries = s.boundaries;
  st.pic_fraction = s.pic_fraction;
  // Contact (Paper III §C.2.7): every body its own fields when a pair has contact or a body
  // is rigid; pairs without a [[contact]] entry stay bonded; hierarchy in body order, each
  // dilated continuum right after its parent (Paper III §C.3.2).
  const bool rigid = std::any_of(s.bodies.begin(), s.bodies.end(), [](const auto& b) { return b.rigid; });
  if (!s.contacts.empty() || rigid) {
    st.contact.resize(static_cast<int>(s.bodies.size()));
    for (std::size_t b = 0; b < s.bodies.size(); ++b) {
      st.contact.rigid[b] = s.bodies[b].rigid;
      st.contact.rigid_velocity[b] = s.bodies[b].velocity;
      if (s.bodies[b].rigid)
        st.contact.outline_normal[b] = [shape = s.bodies[b].shape](const Vec<D>& x) {
          return shape_normal(shape, x);
        };
    }
    for (const ContactPair& c : s.contacts) {
      st.contact.set_friction(c.a, c.b, c.friction);
      st.contact.set_detection(c.a, c.b, c.detection);
    }
    st.contact.order.clear();
    for (std::size_t b = 0; b < s.bodies.size(); ++b) {
      st.contact.parent[b] = s.bodies[b].dilated_from;
      if (s.bodies[b].dilated_from >= 0) continue;
      st.contact.order.push_back(static_cast<int>(b));
      for (std::size_t d = 0; d < s.bodies.size(); ++d)
        if (s.bodies[d].dilated_from == static_cast<int>(b)) st.contact.order.push_back(static_cast<int>(d));
    }
  }
  st.velocity_transfer = s.velocity_transfer;
  st.hyperelastic = s.hyperelastic;
  st.xpic_order = s.xpic_order;
  st.xpic_period = s.xpic_period * stable_time_step(s);  // seconds
  st.volumetric_averaging = s.volumetric_averaging;
  st.centre_shear = s.centre_shear;
  st.geometry = s.geometry;
  return st;
}

template <int D>
ImplicitModel<D> implicit_model(const ScenarioOf<D>& s) {
  ImplicitModel<D> m;
  m.grid = scenario_grid(s);
  m.interpolation = s.interpolation;
  m.quadrature_points = s.quadrature_points;
  m.gravity = s.gravity;
  m.boundaries = s.boundaries;
  m.geometry = s.geometry;
  m.pressures = s.pressures;
  m.volumetric_averaging = s.volumetric_averaging;
  m.prescribed = s.prescribed;
  return m;
}

template <int D>
double stage_time_step(const ScenarioOf<D>& s, const Stage& st) {
  if (st.integrator == IntegratorKind::Explicit) return scenario_time_step(s);
  if (st.implicit.analysis == ImplicitAnalysis::Dynamic) return implicit_time_step(s, st);
  return st.duration / std::max(1, st.implicit.load_steps);
}

template <int D>
GridGeometry<D> scenario_grid(const ScenarioOf<D>& s) {
  GridGeometry<D> grid;
  grid.origin = s.origin;
  grid.h = s.cell_size;
  grid.cells = s.cells;
  return grid;
}

template SolverSettings<2> solver_settings<2>(const Scenario&);
template SolverSettings<3> solver_settings<3>(const Scenario3&);
template ImplicitModel<2> implicit_model<2>(const Scenario&);
template ImplicitModel<3> implicit_model<3>(const Scenario3&);
template double stage_time_step<2>(const Scenario&, const Stage&);
template double stage_time_step<3>(const Scenario3&, const Stage&);
template GridGeometry<2> scenario_grid<2>(const Scenario&);
template GridGeometry<3> scenario_grid<3>(const Scenario3&);

}  // namespace skred
