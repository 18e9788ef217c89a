#include "run/run_summary.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "run/slope_stability.hpp"

namespace skred {

template <int D>
double describe_scenario(Summary& sum, const ScenarioOf<D>& s, long points) {
  sum.scenario = s.source;
  sum.interpolation = to_string(s.interpolation);
  sum.scheme = to_string(s.scheme);
  sum.velocity_transfer = to_string(s.velocity_transfer);
  sum.xpic_order = s.xpic_order;
  sum.xpic_period = s.xpic_period;
  sum.pic_fraction = s.pic_fraction;
  sum.volumetric_strain = s.volumetric_averaging ? "cell-average" : "point";
  // Bishop's F of the bodies at the start (docs/method.md, "Limit equilibrium"); slope_stability
  // builds them afresh, so not for the largest runs.
  if constexpr (D == 2)
    if (points <= 2'000'000) {
      const SlopeStability le = slope_stability(s);
      if (le.computed) {
        sum.limit_equilibrium = le.critical.factor;
        const SlipCircle& c = le.critical.circle;
        sum.slip_circle = {c.xc, c.yc, c.radius, le.critical.x_from, le.critical.x_to};
        return le.critical.factor;
      }
    }
  return NAN;
}

template <int D>
void describe_implicit(Summary& sum, const ScenarioOf<D>& s, const ImplicitSolver<D>& im) {
  const ImplicitTotals& t = im.implicit_totals();
  const Stage* last = nullptr;
  for (const Stage& st : s.stages)
    if (st.integrator == IntegratorKind::Implicit) last = &st;
  sum.implicit = Summary::Implicit{D == 3 ? "3D" : to_string(s.geometry),
                                   to_string(last->implicit.analysis),
                                   to_string(last->implicit.iteration),
                                   t.linear_solver,
                                   t.steps,
                                   t.iterations,
                                   t.factorisations,
                                   t.cut_steps,
                                   t.max_unknowns,
                                   t.max_factor_bytes,
                                   t.elastic_fallbacks};
  const BoundaryForces f = im.clock().boundary_force;
  for (std::size_t b = 0; b < s.prescribed.size(); ++b)
    sum.implicit->forces.emplace_back(s.prescribed[b].name, std::vector<double>(&f[3 * b], &f[3 * b] + D));
}

template double describe_scenario<2>(Summary&, const Scenario&, long);
template double describe_scenario<3>(Summary&, const Scenario3&, long);
template void describe_implicit<2>(Summary&, const Scenario&, const ImplicitSolver<2>&);
template void describe_implicit<3>(Summary&, const Scenario3&, const ImplicitSolver<3>&);

}  // namespace skred
