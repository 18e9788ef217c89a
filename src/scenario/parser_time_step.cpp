// The time step of a scenario checked against the stable explicit step and the step count a run
// may take (scenario/parser.cpp calls it last, once the stages are known).
#include <fmt/format.h>

#include "scenario/estimate.hpp"
#include "scenario/parser_detail.hpp"

namespace skred::scenario_detail {

// Steps a run may take at most: more is a typo (a 1e-300 s step), not an analysis.
constexpr double kMaxSteps = 1e9;

// The time step against the stable explicit step (Thesis §2.2: dt <= h / c) and the number
// of steps the explicit stages take at it; the steps of each dynamic implicit stage.
template <int D>
void check_time_step(const TableReader& root, const ScenarioOf<D>& s) {
  const auto solver = root.table("solver", false);
  const auto stages = root.array_of_tables("stage");  // none: one stage
  double explicit_time = 0.0;                         // the explicit stages' durations
  std::size_t last_explicit = 0;
  for (std::size_t k = 0; k < s.stages.size(); ++k)
    if (s.stages[k].integrator == IntegratorKind::Explicit)
      explicit_time += s.stages[k].duration, last_explicit = k;
  if (s.time_step > 0.0 && explicit_time == 0.0)
    solver->fail_at("time_step",
                    "every stage runs the implicit integrator, which does not read solver.time_step; a "
                    "dynamic implicit stage takes implicit.time_step");
  const double stable = stable_time_step(s);
  if (s.time_step > stable && !s.allow_unstable_time_step)
    solver->fail_at("time_step",
                    fmt::format("{} s exceeds the stable time step h / (c + v0) = {:.4g} s (cell "
                                "size {} m, fastest P-wave speed {:.4g} m/s, fastest initial "
                                "speed v0): the run would blow up. Lower it, use cfl instead, or "
                                "set allow_unstable_time_step = true",
                                s.time_step, stable, s.cell_size, s.cell_size / stable));
  const double dt = scenario_time_step(s);
  const double steps = explicit_time / dt;
  if (!(steps <= kMaxSteps)) {
    const std::string why = fmt::format(
        "the run would take {:.3g} time steps of {:.4g} s over {} s; "
        "at most {:.0e} are allowed",
        steps, dt, explicit_time, kMaxSteps);
    if (s.time_step > 0) solver->fail_at("time_step", why);
    if (last_explicit < stages.size()) stages[last_explicit].fail_at("duration", why);
    solver->fail_at("end_time", why);
  }
  // An explicit stage runs whole steps: one shorter than a step would run a whole step past its
  // end (and a duration of 1e-30 s none at all, "completed" without moving).
  for (std::size_t k = 0; k < s.stages.size(); ++k) {
    const Stage& st = s.stages[k];
    if (st.integrator != IntegratorKind::Explicit || st.duration >= dt * (1.0 - 1e-9)) continue;
    const std::string why = fmt::format(
        "{} s is shorter than one explicit time step ({:.4g} s{}): the stage would run a whole step past "
        "its end; make it at least one step long",
        st.duration, dt, s.time_step > 0.0 ? ", solver.time_step" : ", solver.cfl times h / (c + v0)");
    if (k < stages.size()) stages[k].fail_at("duration", why);
    solver->fail_at("end_time", why);
  }
  const auto implicit = root.table("implicit", false);
  for (std::size_t k = 0; k < s.stages.size(); ++k) {
    const Stage& st = s.stages[k];
    if (st.integrator != IntegratorKind::Implicit || st.implicit.analysis != ImplicitAnalysis::Dynamic)
      continue;
    const double idt = implicit_time_step(s, st);
    if (st.duration / idt <= kMaxSteps) continue;
    const std::string why = fmt::format(
        "stage \"{}\" would take {:.3g} implicit time steps of {:.4g} s over {} s; at most {:.0e} are "
        "allowed",
        st.name, st.duration / idt, idt, st.duration, kMaxSteps);
    if (st.implicit.time_step > 0.0) {
      if (k < stages.size())
        if (const auto own = stages[k].table("implicit", false); own && own->has("time_step"))
          own->follows("implicit").fail_at("time_step", why);
      if (implicit) implicit->fail_at("time_step", why);
    }
    if (k < stages.size()) stages[k].fail_at("duration", why);
    solver->fail_at("end_time", why);
  }
}

template void check_time_step<2>(const TableReader&, const Scenario&);
template void check_time_step<3>(const TableReader&, const Scenario3&);

}  // namespace skred::scenario_detail
