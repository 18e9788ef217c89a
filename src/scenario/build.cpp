#include "scenario/build.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace skred {
namespace {

struct Box {
  Vec<2> lo, hi;
};

Box bounding_box(const Shape& shape) {
  return std::visit(
      [](const auto& sh) -> Box {
        using T = std::decay_t<decltype(sh)>;
        if constexpr (std::is_same_v<T, Rectangle>) {
          return {sh.min, sh.max};
        } else if constexpr (std::is_same_v<T, Disc>) {
          const Vec<2> r = Vec<2>::Constant(sh.radius);
          return {sh.center - r, sh.center + r};
        } else {
          Box b{Vec<2>::Constant(INFINITY), Vec<2>::Constant(-INFINITY)};
          for (const auto& v : sh.vertices) {
            b.lo = b.lo.cwiseMin(v);
            b.hi = b.hi.cwiseMax(v);
          }
          return b;
        }
      },
      shape);
}

// Calls f(point) for every sub-square centre of the body's bounding-box cells that lies inside
// the shape, cells in row-major order (x fastest), then sub-squares in row-major order. Stops
// early when f returns false.
template <class F> void for_each_point(const Scenario& s, const Body& body, F&& f) {
  const double h = s.cell_size;
  const int n = body.particles_per_cell;
  if (!(h > 0.0) || n < 1 || s.cells[0] < 1 || s.cells[1] < 1) return;
  const double sub = h / n;
  const Box box = bounding_box(body.shape);
  int lo[2], hi[2];
  for (int d = 0; d < 2; ++d) {
    const double a = std::floor((box.lo[d] - s.origin[d]) / h);
    const double b = std::floor((box.hi[d] - s.origin[d]) / h);
    if (!(b >= 0.0) || !(a <= s.cells[d] - 1.0)) return;  // entirely outside the grid
    lo[d] = static_cast<int>(std::max(a, 0.0));
    hi[d] = static_cast<int>(std::min(b, s.cells[d] - 1.0));
  }
  for (int j = lo[1]; j <= hi[1]; ++j)
    for (int i = lo[0]; i <= hi[0]; ++i)
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) {
          const Vec<2> x(s.origin[0] + i * h + (a + 0.5) * sub,
                         s.origin[1] + j * h + (b + 0.5) * sub);
          if (shape_contains(body.shape, x) && !f(x)) return;
        }
}

// The strength parameters of a material, for describe().
std::string strength_summary(const Material& m) {
  constexpr double deg = 180.0 / M_PI;
  switch (m.model) {
    case Model::LinearElastic: return "";
    case Model::MohrCoulomb: {
      const auto& mc = m.mohr_coulomb;
      std::string t = fmt::format(", friction {:.4g} deg, cohesion {} Pa, dilation {:.4g} deg",
                                  mc.friction * deg, mc.cohesion, mc.dilation * deg);
      if (std::isfinite(mc.tension_cutoff)) t += fmt::format(", tension cut-off {} Pa", mc.tension_cutoff);
      if (mc.max_void_ratio > 0)
        t += fmt::format(", void ratio {} -> max {}", mc.initial_void_ratio, mc.max_void_ratio);
      return t;
    }
    case Model::Tresca: return fmt::format(", cohesion {} Pa", m.mohr_coulomb.cohesion);
    case Model::VonMises:
      return fmt::format(", cohesion {} Pa -> residual {} Pa, softening modulus {} Pa",
                         m.von_mises.cohesion_peak, m.von_mises.cohesion_residual,
                         m.von_mises.softening_modulus);
  }
  return "";
}

std::string stage_summary(const Scenario& s, const Stage& st) {
  std::string t = fmt::format("  {}: {} s", st.name, st.duration);
  if (st.gravity_ramp_time > 0) t += fmt::format(", gravity ramp {} s", st.gravity_ramp_time);
  if (st.elastic) t += ", held elastic";
  if (st.strength_reduction != 1.0) t += fmt::format(", strength reduction {}", st.strength_reduction);
  for (const auto& o : st.overrides) {
    t += fmt::format(", {}:", s.materials[static_cast<std::size_t>(o.material)].name);
    if (o.friction) t += fmt::format(" friction {:.4g} deg", *o.friction * 180.0 / M_PI);
    if (o.cohesion) t += fmt::format(" cohesion {} Pa", *o.cohesion);
    if (o.dilation) t += fmt::format(" dilation {:.4g} deg", *o.dilation * 180.0 / M_PI);
  }
  if (st.rest_speed > 0)
    t += fmt::format(", ends when the mean speed stays below {} m/s for {} s", st.rest_speed,
                     st.rest_time);
  return t;
}

std::string vec(const Vec<2>& v) { return fmt::format("({}, {})", v[0], v[1]); }

std::string shape_summary(const Shape& shape) {
  return std::visit(
      [](const auto& sh) -> std::string {
        using T = std::decay_t<decltype(sh)>;
        if constexpr (std::is_same_v<T, Rectangle>) {
          return fmt::format("rectangle {} to {}", vec(sh.min), vec(sh.max));
        } else if constexpr (std::is_same_v<T, Disc>) {
          return fmt::format("disc centre {} radius {} m", vec(sh.center), sh.radius);
        } else {
          return fmt::format("polygon with {} vertices, area {} m^2", sh.vertices.size(),
                             std::abs(polygon_area(sh)));
        }
      },
      shape);
}

std::string boundary_summary(const BoundarySide& b) {
  if (b.kind == BoundaryKind::Friction) return fmt::format("friction (mu = {})", b.friction);
  return to_string(b.kind);
}

}  // namespace

bool shape_contains(const Shape& shape, const Vec<2>& x) {
  if (const auto* r = std::get_if<Rectangle>(&shape))
    return x[0] >= r->min[0] && x[0] < r->max[0] && x[1] >= r->min[1] && x[1] < r->max[1];
  if (const auto* c = std::get_if<Disc>(&shape)) return (x - c->center).squaredNorm() < c->radius * c->radius;
  // Crossing number: count edges crossed by the ray from x towards +x. An edge covers the
  // half-open span [low y, high y); evaluating it from its low end makes the intersection
  // bit-identical for two polygons that share the edge in opposite directions.
  const auto& v = std::get<Polygon>(shape).vertices;
  bool inside = false;
  for (std::size_t k = 0, m = v.size(); k < m; ++k) {
    const Vec<2>* p = &v[k];
    const Vec<2>* q = &v[(k + 1) % m];
    if ((*p)[1] > (*q)[1]) std::swap(p, q);
    if (!(x[1] >= (*p)[1] && x[1] < (*q)[1])) continue;
    const double xi = (*p)[0] + (x[1] - (*p)[1]) * ((*q)[0] - (*p)[0]) / ((*q)[1] - (*p)[1]);
    if (x[0] < xi) inside = !inside;
  }
  return inside;
}

double polygon_area(const Polygon& p) {
  double a = 0.0;
  const auto& v = p.vertices;
  for (std::size_t k = 0, m = v.size(); k < m; ++k) {
    const auto& u = v[k];
    const auto& w = v[(k + 1) % m];
    a += u[0] * w[1] - w[0] * u[1];
  }
  return 0.5 * a;
}

std::size_t count_points(const Scenario& s, const Body& b) {
  std::size_t n = 0;
  for_each_point(s, b, [&](const Vec<2>&) { return ++n, true; });
  return n;
}

bool has_points(const Scenario& s, const Body& b) {
  bool any = false;
  for_each_point(s, b, [&](const Vec<2>&) { return any = true, false; });
  return any;
}

Particles<2> build_particles(const Scenario& s) {
  if (s.bodies.size() > static_cast<std::size_t>(kMaxIds) ||
      s.materials.size() > static_cast<std::size_t>(kMaxIds))
    throw ScenarioError(fmt::format("{}: at most {} bodies and {} materials are supported",
                                    s.source, kMaxIds, kMaxIds));
  std::vector<std::size_t> counts;
  std::size_t total = 0;
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    counts.push_back(count_points(s, s.bodies[i]));
    if (counts.back() == 0)
      throw ScenarioError(fmt::format(
          "{}: key 'body[{}].shape': body '{}' contains no material point on this grid "
          "(cell size {} m, {} points per cell); enlarge the shape or refine the grid",
          s.source, i, s.bodies[i].name, s.cell_size, s.bodies[i].particles_per_cell));
    total += counts.back();
  }
  Particles<2> p;
  p.reserve(total);
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const Body& b = s.bodies[i];
    const Material& mat = s.materials.at(static_cast<std::size_t>(b.material));
    const double sub = s.cell_size / b.particles_per_cell;
    const double volume = sub * sub;
    const Vec<2> half = Vec<2>::Constant(0.5 * sub);
    for_each_point(s, b, [&](const Vec<2>& x) {
      Vec<2> v = b.velocity;
      const SineVelocity& sv = b.velocity_sine;
      if (sv.wavelength > 0.0)
        v += sv.amplitude * std::sin(2.0 * M_PI * (x[sv.axis] - sv.origin) / sv.wavelength);
      p.add(x, v, mat.density * volume, volume, half, b.material, static_cast<int>(i));
      return true;
    });
  }
  return p;
}

std::string describe(const Scenario& s) {
  std::string out;
  auto line = [&out](const std::string& text) { out += text + '\n'; };
  line(fmt::format("scenario: {}{}", s.source, s.title.empty() ? "" : " (\"" + s.title + "\")"));
  line(fmt::format("grid: {} x {} cells of {} m, origin {}, extent {} x {} m", s.cells[0],
                   s.cells[1], s.cell_size, vec(s.origin), s.cells[0] * s.cell_size,
                   s.cells[1] * s.cell_size));
  line(fmt::format("materials ({}):", s.materials.size()));
  for (const auto& m : s.materials)
    line(fmt::format("  {}: {}, density {} kg/m^3, young {} Pa, poisson {}{}", m.name,
                     to_string(m.model), m.density, m.elastic.young, m.elastic.poisson,
                     strength_summary(m)));
  line(fmt::format("bodies ({}):", s.bodies.size()));
  for (const auto& b : s.bodies) {
    const std::string mat = b.material >= 0 && static_cast<std::size_t>(b.material) < s.materials.size()
                                ? s.materials[static_cast<std::size_t>(b.material)].name
                                : "?";
    line(fmt::format("  {}: {}, material {}, {}x{} points per cell, velocity {} m/s", b.name,
                     shape_summary(b.shape), mat, b.particles_per_cell, b.particles_per_cell,
                     vec(b.velocity)));
  }
  line(fmt::format("gravity: {} m/s^2", vec(s.gravity)));
  switch (s.initial_stress.rule) {
    case K0Rule::None: break;
    case K0Rule::Poisson: line("initial stress: K0 = nu / (1 - nu) from the overburden"); break;
    case K0Rule::Jaky: line("initial stress: K0 = 1 - sin(phi) from the overburden"); break;
    case K0Rule::Value: line(fmt::format("initial stress: K0 = {} from the overburden", s.initial_stress.k0)); break;
  }
  line(fmt::format("stages ({}):", s.stages.size()));
  for (const auto& st : s.stages) line(stage_summary(s, st));
  line(fmt::format("boundaries: x_min {}, x_max {}, y_min {}, y_max {}",
                   boundary_summary(s.boundaries[0]), boundary_summary(s.boundaries[1]),
                   boundary_summary(s.boundaries[2]), boundary_summary(s.boundaries[3])));
  std::string interp = to_string(s.interpolation);
  if (s.interpolation == Interpolation::GimpQuadrature)
    interp += fmt::format(" ({} points per direction)", s.quadrature_points);
  const std::string step = s.time_step > 0.0 ? fmt::format("time step {} s", s.time_step)
                                             : fmt::format("time step from CFL {}", s.cfl);
  line(fmt::format("solver: {} interpolation, {} scheme, end time {} s, {}", interp,
                   to_string(s.scheme), s.end_time, step));
  line(fmt::format("output: particle frames every {} s, series rows every {} s",
                   s.output_interval, s.series_interval));
  return out;
}

}  // namespace skred
