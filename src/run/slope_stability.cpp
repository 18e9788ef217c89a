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

// The columns of a section's profile: where the first starts along the section and how many.
struct Columns {
  double x0 = 0.0;
  int count = 0;
};

// The layers: in each cell of the section's plane the material with the most mass of the
// ground's points whose centres lie in it, as an index into `used`.
template <int D>
void fill_layers(const ScenarioOf<D>& s, const Particles<2>& P, const std::vector<int>& used, Columns cols,
                 GroundProfile& g) {
  g.rows = s.cells[1], g.row0 = s.origin[1], g.row_height = s.cell_size;
  const std::size_t cells = static_cast<std::size_t>(cols.count) * static_cast<std::size_t>(g.rows);
  std::vector<double> mass(cells * used.size(), 0.0);
  for (std::size_t p = 0; p < P.size(); ++p) {
    const auto cell = [&](double x, double x0, int n) {
      const double u = std::floor((x - x0) / s.cell_size);
      return static_cast<std::size_t>(std::clamp(u, 0.0, n - 1.0));
    };
    const std::size_t at = cell(P.x[p][0], cols.x0, cols.count) * static_cast<std::size_t>(g.rows) +
                           cell(P.x[p][1], g.row0, g.rows);
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

// What the check takes from a scenario: the last stage that lets the soil yield, the deformable
// bodies' materials and their strength in it; `why_not` when there is no check to make.
struct Ground {
  std::string why_not;
  const Stage* stage = nullptr;
  std::vector<int> used;  // the deformable bodies' materials, in the order the bodies give them
  std::vector<SoilStrength> soils;
  std::vector<std::string> yielding;
};

Ground refused(std::string why) {
  Ground gr;
  gr.why_not = std::move(why);
  return gr;
}

template <int D>
Ground ground_of(const ScenarioOf<D>& s) {
  Ground gr;
  for (const Stage& st : s.stages)
    if (!st.elastic) gr.stage = &st;
  if (!gr.stage) return refused("every stage holds the materials elastic");
  if (s.geometry == Geometry::Axisymmetric)  // Bishop's slices are plane strain
    return refused("the circles are plane strain; this section is axisymmetric");
  if (s.gravity.norm() == 0.0) return refused("no gravity");
  if (!(s.gravity[1] < 0.0) || s.gravity[0] != 0.0 || (D == 3 && s.gravity[D - 1] != 0.0))
    return refused("gravity is not along -y");
  for (const BodyOf<D>& b : s.bodies)
    if (!b.rigid && b.dilated_from < 0 &&
        std::find(gr.used.begin(), gr.used.end(), b.material) == gr.used.end())
      gr.used.push_back(b.material);
  if (gr.used.empty()) return refused("no deformable body");
  const std::vector<Material> materials = stage_materials(s, *gr.stage);
  std::vector<std::string> names;
  for (int k : gr.used) {
    const Material& m = materials[static_cast<std::size_t>(k)];
    gr.soils.push_back({m.strength_cohesion(), m.friction_angle(), m.density * -s.gravity[1], !m.plastic()});
    names.push_back(fmt::format("'{}'", m.name));
    if (m.plastic()) gr.yielding.push_back(m.name);
  }
  if (gr.yielding.empty())
    return refused(fmt::format("{} {} {} not yield", gr.used.size() > 1 ? "materials" : "material",
                               fmt::join(names, ", "), gr.used.size() > 1 ? "do" : "does"));
  return gr;
}

// Bishop's critical circle of the ground's points P in a section's plane (the other points
// erased): x along the section, from the columns `cols`, and y.
template <int D>
SlopeStability bishop_of(const ScenarioOf<D>& s, const Ground& gr, Particles<2>& P, Columns cols) {
  std::vector<std::uint8_t> keep(P.size());  // the deformable bodies' points only
  for (std::size_t p = 0; p < P.size(); ++p) {
    const BodyOf<D>& b = s.bodies[static_cast<std::size_t>(P.body[p])];
    keep[p] = !b.rigid && std::find(gr.used.begin(), gr.used.end(), P.material[p]) != gr.used.end();
  }
  P.erase(keep);
  if (P.size() == 0) return not_computed("no material points");

  GroundProfile g;
  g.x0 = cols.x0, g.width = s.cell_size;
  const SurfaceProfile prof = surface_profile(P, g.x0, g.width, cols.count);
  g.base = INFINITY;
  for (std::size_t p = 0; p < P.size(); ++p) g.base = std::min(g.base, P.x[p][1] - P.half0[p][1]);
  g.top = prof.top;
  for (double& t : g.top)
    if (!std::isfinite(t)) t = NAN;
  // The points know the surface to a cell: a slip thinner than that is their steps', not the
  // ground's (a 30 deg sand slope at phi = 35 deg gave F = 0.70 on 1 m cells, 1.22 with this;
  // LimitEquilibrium.CohesionlessSlopeOfPointsHasTheInfiniteSlopesFactor).
  g.min_depth = s.cell_size;
  if (gr.used.size() > 1) fill_layers(s, P, gr.used, cols, g);

  SlopeStability r;
  r.computed = true;
  r.stage = gr.stage->name;
  r.materials = gr.yielding;
  r.critical = critical_circle(g, gr.soils);
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

}  // namespace

SlopeStability slope_stability(const Scenario& s) {
  const Ground gr = ground_of(s);
  if (!gr.why_not.empty()) return not_computed(gr.why_not);
  Particles<2> P = build_particles(s);
  return bishop_of(s, gr, P, {s.origin[0], s.cells[0]});
}

SlopeStability slope_stability(const Scenario3& s) {
  const Ground gr = ground_of(s);
  if (!gr.why_not.empty()) return not_computed(gr.why_not);
  const Particles<3> P = build_particles(s);
  // The ground's top in each x-z column of cells (its points' highest edge y + l_y).
  const int nx = s.cells[0], nz = s.cells[2];
  std::vector<double> top(static_cast<std::size_t>(nx) * nz, -INFINITY);
  const auto cell = [&](const Vec<3>& x, int axis, int n) {
    return static_cast<int>(std::clamp(std::floor((x[axis] - s.origin[axis]) / s.cell_size), 0.0, n - 1.0));
  };
  for (std::size_t p = 0; p < P.size(); ++p) {
    const BodyOf<3>& b = s.bodies[static_cast<std::size_t>(P.body[p])];
    if (b.rigid || std::find(gr.used.begin(), gr.used.end(), P.material[p]) == gr.used.end()) continue;
    double& t = top[static_cast<std::size_t>(cell(P.x[p], 2, nz)) * nx + cell(P.x[p], 0, nx)];
    t = std::max(t, P.x[p][1] + P.half0[p][1]);
  }
  // The steepest section: of the rows of cells along x and the columns along z, the one whose
  // tops have the largest mean gradient (a slope need not fall along x).
  const auto top_at = [&](int i, int k) { return top[static_cast<std::size_t>(k) * nx + i]; };
  const auto mean_gradient = [&](int n, auto&& height) {
    double sum = 0.0;
    int count = 0;
    for (int i = 0; i + 1 < n; ++i) {
      const double a = height(i), b = height(i + 1);
      if (std::isfinite(a) && std::isfinite(b)) sum += std::abs(b - a) / s.cell_size, ++count;
    }
    return count > 0 ? sum / count : -1.0;
  };
  int steepest = -1, along = 0;  // along: 0 a row along x at z cell `steepest`, 2 a column along z
  double slope = -1.0;
  for (int k = 0; k < nz; ++k)
    if (const double m = mean_gradient(nx, [&](int i) { return top_at(i, k); }); m > slope)
      slope = m, steepest = k, along = 0;
  for (int i = 0; i < nx; ++i)
    if (const double m = mean_gradient(nz, [&](int k) { return top_at(i, k); }); m > slope)
      slope = m, steepest = i, along = 2;
  if (steepest < 0) return not_computed("no ground two cells long along x or z");
  const int across = 2 - along;  // the axis whose cell holds the section
  Particles<2> section;          // the points in that row or column, as plane strain
  for (std::size_t p = 0; p < P.size(); ++p)
    if (cell(P.x[p], across, s.cells[across]) == steepest)
      section.add(Vec<2>(P.x[p][along], P.x[p][1]), Vec<2>::Zero(), P.mass[p], P.volume0[p],
                  Vec<2>(P.half0[p][along], P.half0[p][1]), P.material[p], P.body[p]);
  SlopeStability r = bishop_of(s, gr, section, {s.origin[along], s.cells[along]});
  r.axis = along == 0 ? 'x' : 'z';
  const double c0 = s.origin[across] + steepest * s.cell_size;
  r.section = fmt::format(
      "on the 2D section of the cells {} = {:.6g} to {:.6g} m along {}, the steepest (mean "
      "slope {:.1f} deg), as plane strain",
      across == 2 ? "z" : "x", c0, c0 + s.cell_size, along == 0 ? "x" : "z", std::atan(slope) * 180.0 / M_PI);
  return r;
}

std::string slope_stability_line(const SlopeStability& r) {
  if (!r.computed) return fmt::format("limit equilibrium: not computed ({})\n", r.why_not);
  const CriticalCircle& c = r.critical;
  return fmt::format(
      "limit equilibrium (Bishop's simplified method on circles, dry, {} in stage '{}'{}): "
      "F = {:.3f} on the circle centred ({:.2f}, {:.2f}) m of radius {:.2f} m, sliding towards {}{}: {}{}\n",
      r.materials.size() == 1 ? r.materials.front() + "'s strength"
                              : fmt::format("the strengths of {}", fmt::join(r.materials, ", ")),
      r.stage, r.section.empty() ? "" : ", " + r.section, c.factor, c.circle.xc, c.circle.yc, c.circle.radius,
      c.direction > 0 ? "+" : "-", r.axis,
      c.factor < 1.0 ? fmt::format("the slope is not expected to stand: its {} {:.0f} % of the strength {} "
                                   "(the nearer 100 %, the more a slide's runout depends on the cell)",
                                   r.materials.size() == 1 ? "soil has" : "soils have", 100.0 * c.factor,
                                   r.materials.size() == 1 ? "it needs" : "they need")
                     : std::string("the slope is expected to stand"),
      r.note.empty() ? "" : "; note: " + r.note);
}

}  // namespace skred
