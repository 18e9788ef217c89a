// The stress-update schemes of Thesis §4.4 as small types that order the phases of the
// explicit step. The phases themselves (explicit_solver_impl.hpp, grid_phases.cpp) do not know
// which scheme calls them. Every scheme starts from the grid's mass and momentum of the
// step (eq. 2.53-2.54), mapped by the last phase of the step before or by
// ExplicitSolver::map_grid, and ends by mapping the next step's (the fused map).
#pragma once

namespace skred {

enum class StressScheme { USF, USL, Averaged };

inline const char* to_string(StressScheme s) {
  switch (s) {
    case StressScheme::USF: return "usf";
    case StressScheme::USL: return "usl";
    case StressScheme::Averaged: return "averaged";
  }
  return "?";
}

// Update stress first: the strain increment from v_i^k, then the momentum update.
struct UpdateStressFirst {
  template <class Solver, class K>
  static bool advance(Solver& s, const K& kernel) {
    s.nodal_velocity();                                                     // v_i^k (eq. 2.23)
    if (!s.stress_update_and_internal_force(kernel, s.dt())) return false;  // eq. 2.20, 4.1-4.4, 2.51
    s.grid_update();                                                        // eq. 2.49, 5.8-5.11
    s.contact();
    return s.velocity_move_and_map(kernel);  // eq. 2.55-2.56, 2.53-2.54
  }
};

// Update stress last: forces from sigma^k, the momentum update, the updated particle momenta
// mapped back to the grid (the momentum remap; Acosta's "double mapping" is another thing, of
// stresses), and the stress update from those velocities.
struct UpdateStressLast {
  template <class Solver, class K>
  static bool advance(Solver& s, const K& kernel) {
    s.nodal_velocity();        // v_i^k (eq. 2.23)
    s.internal_force(kernel);  // f_i^int from sigma^k (eq. 2.51)
    s.grid_update();           // eq. 2.49, 5.8-5.11
    s.contact();
    s.velocity_and_remap(kernel);                         // v_p^{k+1} (eq. 2.56), p~_i = sum N m_p v_p^{k+1}
    s.remap_velocity();                                   // v~_i = p~_i / m_i
    return s.stress_update_move_and_map(kernel, s.dt());  // eq. 2.20, 4.1-4.4, 2.55, 2.53-2.54
  }
};

// The averaged scheme: half the stress update from v_i^k before the momentum update, half
// from the remapped v~_i after it (Thesis §4.4, fig. 4.6: conserves energy).
struct AveragedScheme {
  template <class Solver, class K>
  static bool advance(Solver& s, const K& kernel) {
    const double half_dt = 0.5 * s.dt();
    s.nodal_velocity();
    if (!s.stress_update_and_internal_force(kernel, half_dt)) return false;
    s.grid_update();
    s.contact();
    s.velocity_and_remap(kernel);
    s.remap_velocity();
    return s.stress_update_move_and_map(kernel, half_dt);
  }
};

// f(scheme) with the scheme type of `s`.
template <class F>
decltype(auto) with_scheme(StressScheme s, F&& f) {
  switch (s) {
    case StressScheme::USF: return f(UpdateStressFirst{});
    case StressScheme::USL: return f(UpdateStressLast{});
    case StressScheme::Averaged: break;
  }
  return f(AveragedScheme{});
}

}  // namespace skred
