#include "run/slope_stability.hpp"

#include <fmt/core.h>

#include <cmath>

#include "run/slide_measures.hpp"
#include "scenario/build.hpp"
#include "scenario/initial_stress.hpp"

namespace skred {

namespace {

SlopeStability not_computed(std::string why) {
  SlopeStability r;
  r.why_not = std::move(why);
  return r;
}

}  // namespace

SlopeStability slope_stability(const Scenario& s) {
  const Stage* stage = nullptr;  // the last stage that lets the soil yield
  for (const Stage& st : s.stages)
    if (!st.elastic) stage = &st;
  if (!stage) return not_computed("every stage holds the materials elastic");
  if (s.gravity.norm() == 0.0) return not_computed("no gravity");
  if (!(s.gravity[1] < 0.0) || s.gravity[0] != 0.0) return not_computed("gravity is not along -y");
  int material = -1;
  for (const Body& b : s.bodies) {
    if (b.rigid || b.dilated_from >= 0) continue;
    if (material >= 0 && b.material != material)
      return not_computed("the bodies are of more than one material");
    material = b.material;
  }
  if (material < 0) return not_computed("no deformable body");
  const Material m = stage_materials(s, *stage)[static_cast<std::size_t>(material)];
  if (!m.plastic()) return not_computed(fmt::format("material '{}' does not yield", m.name));

  Particles<2> P = build_particles(s);
  std::vector<std::uint8_t> keep(P.size());  // the deformable bodies' points only
  for (std::size_t p = 0; p < P.size(); ++p)
    keep[p] = P.material[p] == material && !s.bodies[static_cast<std::size_t>(P.body[p])].rigid;
  P.erase(keep);
  if (P.size() == 0) return not_computed("no material points");

  GroundProfile g;
  g.x0 = s.origin[0], g.width = s.cell_size;
  const SurfaceProfile prof = surface_profile(P, g.x0, g.width, s.cells[0]);
  g.base = INFINITY;
  for (std::size_t p = 0; p < P.size(); ++p) g.base = std::min(g.base, P.x[p][1] - P.half0[p][1]);
  g.top = prof.top;
  for (double& t : g.top)
    if (!std::isfinite(t)) t = NAN;

  SlopeStability r;
  r.computed = true;
  r.stage = stage->name;
  r.material = m.name;
  r.critical = critical_circle(g, {m.strength_cohesion(), m.friction_angle(), m.density * -s.gravity[1]});
  if (!std::isfinite(r.critical.factor)) return not_computed("no slip circle cuts the ground");
  return r;
}

std::string slope_stability_line(const SlopeStability& r) {
  if (!r.computed) return fmt::format("limit equilibrium: not computed ({})\n", r.why_not);
  const CriticalCircle& c = r.critical;
  return fmt::format(
      "limit equilibrium (Bishop's simplified method on circles, dry, {}'s strength in stage '{}'): "
      "F = {:.3f} on the circle centred ({:.2f}, {:.2f}) m of radius {:.2f} m, sliding towards {}x: {}\n",
      r.material, r.stage, c.factor, c.circle.xc, c.circle.yc, c.circle.radius, c.direction > 0 ? "+" : "-",
      c.factor < 1.0
          ? fmt::format("the slope is not expected to stand: its soil has {:.0f} % of the strength it needs "
                        "(the nearer 100 %, the more a slide's runout depends on the cell)",
                        100.0 * c.factor)
          : std::string("the slope is expected to stand"));
}

}  // namespace skred
