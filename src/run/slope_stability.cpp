#include "run/slope_stability.hpp"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
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

// The layers: in each cell of the grid the material with the most mass of the ground's points
// whose centres lie in it, as an index into `used`.
void fill_layers(const Scenario& s, const Particles<2>& P, const std::vector<int>& used, GroundProfile& g) {
  g.rows = s.cells[1], g.row0 = s.origin[1], g.row_height = s.cell_size;
  const std::size_t cells = static_cast<std::size_t>(s.cells[0]) * static_cast<std::size_t>(g.rows);
  std::vector<double> mass(cells * used.size(), 0.0);
  for (std::size_t p = 0; p < P.size(); ++p) {
    const auto cell = [&](int axis, int n) {
      const double u = std::floor((P.x[p][axis] - s.origin[axis]) / s.cell_size);
      return static_cast<std::size_t>(std::clamp(u, 0.0, n - 1.0));
    };
    const std::size_t at = cell(0, s.cells[0]) * static_cast<std::size_t>(g.rows) + cell(1, g.rows);
    const auto k = std::find(used.begin(), used.end(), P.material[p]) - used.begin();
    mass[at * used.size() + static_cast<std::size_t>(k)] += P.mass[p];
  }
  g.soil.assign(cells, GroundProfile::kNoSoil);
  for (std::size_t at = 0; at < cells; ++at) {
    const auto first = mass.begin() + static_cast<std::ptrdiff_t>(at * used.size());
    const auto most = std::max_element(first, first + static_cast<std::ptrdiff_t>(used.size()));
    if (*most > 0.0) g.soil[at] = static_cast<int>(most - first);
  }
}

}  // namespace

SlopeStability slope_stability(const Scenario& s) {
  const Stage* stage = nullptr;  // the last stage that lets the soil yield
  for (const Stage& st : s.stages)
    if (!st.elastic) stage = &st;
  if (!stage) return not_computed("every stage holds the materials elastic");
  if (s.geometry == Geometry::Axisymmetric)  // Bishop's slices are plane strain
    return not_computed("the circles are plane strain; this section is axisymmetric");
  if (s.gravity.norm() == 0.0) return not_computed("no gravity");
  if (!(s.gravity[1] < 0.0) || s.gravity[0] != 0.0) return not_computed("gravity is not along -y");
  std::vector<int> used;  // the deformable bodies' materials, in the order the bodies give them
  for (const Body& b : s.bodies)
    if (!b.rigid && b.dilated_from < 0 && std::find(used.begin(), used.end(), b.material) == used.end())
      used.push_back(b.material);
  if (used.empty()) return not_computed("no deformable body");
  const std::vector<Material> materials = stage_materials(s, *stage);
  std::vector<SoilStrength> soils;
  std::vector<std::string> names, yielding;
  for (int k : used) {
    const Material& m = materials[static_cast<std::size_t>(k)];
    soils.push_back({m.strength_cohesion(), m.friction_angle(), m.density * -s.gravity[1], !m.plastic()});
    names.push_back(fmt::format("'{}'", m.name));
    if (m.plastic()) yielding.push_back(m.name);
  }
  if (yielding.empty())
    return not_computed(fmt::format("{} {} {} not yield", used.size() > 1 ? "materials" : "material",
                                    fmt::join(names, ", "), used.size() > 1 ? "do" : "does"));

  Particles<2> P = build_particles(s);
  std::vector<std::uint8_t> keep(P.size());  // the deformable bodies' points only
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Body& b = s.bodies[static_cast<std::size_t>(P.body[p])];
    keep[p] = !b.rigid && std::find(used.begin(), used.end(), P.material[p]) != used.end();
  }
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
  if (used.size() > 1) fill_layers(s, P, used, g);

  SlopeStability r;
  r.computed = true;
  r.stage = stage->name;
  r.materials = yielding;
  r.critical = critical_circle(g, soils);
  for (const ContactPair& c : s.contacts)  // the first interface inside the ground
    if (!s.bodies[static_cast<std::size_t>(c.a)].rigid && !s.bodies[static_cast<std::size_t>(c.b)].rigid) {
      r.note = fmt::format(
          "the contact between '{}' and '{}' (mu = {}) is not a weakness to it: a circle crosses it with the "
          "soils' strength, and a slide along it may need less",
          s.bodies[static_cast<std::size_t>(c.a)].name, s.bodies[static_cast<std::size_t>(c.b)].name,
          c.friction);
      break;
    }
  if (!std::isfinite(r.critical.factor)) return not_computed("no slip circle cuts the ground");
  return r;
}

std::string slope_stability_line(const SlopeStability& r) {
  if (!r.computed) return fmt::format("limit equilibrium: not computed ({})\n", r.why_not);
  const CriticalCircle& c = r.critical;
  return fmt::format(
      "limit equilibrium (Bishop's simplified method on circles, dry, {} in stage '{}'): "
      "F = {:.3f} on the circle centred ({:.2f}, {:.2f}) m of radius {:.2f} m, sliding towards {}x: {}{}\n",
      r.materials.size() == 1 ? r.materials.front() + "'s strength"
                              : fmt::format("the strengths of {}", fmt::join(r.materials, ", ")),
      r.stage, c.factor, c.circle.xc, c.circle.yc, c.circle.radius, c.direction > 0 ? "+" : "-",
      c.factor < 1.0 ? fmt::format("the slope is not expected to stand: its {} {:.0f} % of the strength {} "
                                   "(the nearer 100 %, the more a slide's runout depends on the cell)",
                                   r.materials.size() == 1 ? "soil has" : "soils have", 100.0 * c.factor,
                                   r.materials.size() == 1 ? "it needs" : "they need")
                     : std::string("the slope is expected to stand"),
      r.note.empty() ? "" : "; note: " + r.note);
}

}  // namespace skred
