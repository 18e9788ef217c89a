// The dimension-dependent tables of a scenario file: [grid], [[body]] (2D shapes here, 3D
// shapes in parser_shapes3.cpp), [gravity] and [boundary]. docs/scenario.md documents them.
#include <cmath>

#include "scenario/build.hpp"
#include "scenario/parser_detail.hpp"

namespace skred::scenario_detail {

namespace {

constexpr int kMaxCells = 100000;

Shape parse_rectangle(const TableReader& b, const Scenario& s) {
  Rectangle r{b.vec<2>("min"), b.vec<2>("max")};
  if (!(r.max[0] > r.min[0] && r.max[1] > r.min[1]))
    b.fail_at("max", fmt::format("max ({}, {}) must exceed min ({}, {}) in both components", r.max[0],
                                 r.max[1], r.min[0], r.min[1]));
  check_inside(b, "min", s, r.min, "min corner");
  check_inside(b, "max", s, r.max, "max corner");
  return r;
}

Shape parse_polygon(const TableReader& b, const Scenario& s) {
  return parse_vertices(b, s.origin, grid_high(s), grid_tolerance(s), grid_bounds(s));
}

Shape parse_disc(const TableReader& b, const Scenario& s) {
  Disc c{b.vec<2>("center"), b.number("radius")};
  check_inside(b, "center", s, c.center, "centre");
  const Vec<2> r = Vec<2>::Constant(c.radius);
  if (!inside_grid(s, Vec<2>(c.center - r)) || !inside_grid(s, Vec<2>(c.center + r)))
    b.fail_at("radius", fmt::format("the disc of radius {} around ({}, {}) extends outside the "
                                    "grid {}",
                                    c.radius, c.center[0], c.center[1], grid_bounds(s)));
  return c;
}

// The body's keys and those of its shape are allowed; the shape's are read against its
// schema section.
Shape parse_shape2(const TableReader& t, const Scenario& s) {
  enum class Kind { Rectangle, Polygon, Disc, Layer };
  const Kind kind = t.choice<Kind>("shape", {{"rectangle", Kind::Rectangle},
                                             {"polygon", Kind::Polygon},
                                             {"disc", Kind::Disc},
                                             {"layer", Kind::Layer}});
  const char* section = kind == Kind::Rectangle ? "body (rectangle)"
                        : kind == Kind::Polygon ? "body (polygon)"
                        : kind == Kind::Layer   ? "body (layer)"
                                                : "body (disc)";
  t.allow_declared(&schema::section(section));
  const TableReader shape = t.follows(section);
  switch (kind) {
    case Kind::Rectangle: return parse_rectangle(shape, s);
    case Kind::Polygon: return parse_polygon(shape, s);
    case Kind::Layer: return parse_layer(shape, s);
    case Kind::Disc: break;
  }
  return parse_disc(shape, s);
}

}  // namespace

Polygon parse_vertices(const TableReader& b, const Vec<2>& lo, const Vec<2>& hi, double tol,
                       const std::string& bounds) {
  if (!b.has("vertices")) b.fail_missing("vertices");
  const auto* arr = b.find("vertices")->as_array();
  if (!arr) b.fail_type("vertices", "an array of [x, y] pairs");
  if (arr->size() < 3)
    b.fail_at("vertices", fmt::format("a polygon needs at least 3 vertices, got {}", arr->size()));
  Polygon p;
  for (std::size_t k = 0; k < arr->size(); ++k) {
    const std::string key = fmt::format("{}[{}]", b.key("vertices"), k);
    const Vec<2> v = node_vec2(*arr->get(k), b.source(), key, b.where("vertices"));
    if (!((v.array() >= lo.array() - tol).all() && (v.array() <= hi.array() + tol).all()))
      fail(b.source(), location_of(arr->get(k)->source(), b.where("vertices")), key,
           fmt::format("vertex ({}, {}) lies outside the grid {}", v[0], v[1], bounds));
    p.vertices.push_back(v);
  }
  Vec<2> a = p.vertices[0], c = p.vertices[0];
  for (const auto& v : p.vertices) a = a.cwiseMin(v), c = c.cwiseMax(v);
  const Vec<2> span = c - a;
  if (!(std::abs(polygon_area(p)) > 1e-12 * span.squaredNorm()))
    b.fail_at("vertices", "the polygon has zero area");
  return p;
}

template <int D>
void parse_grid(const TableReader& root, ScenarioOf<D>& s) {
  const TableReader g = *root.table("grid", true);
  g.allow_declared();
  s.origin = g.vec_or<D>("origin", Vec<D>::Zero());
  const Vec<D> size = g.vec<D>("size");
  const double h = g.number("cell_size");
  for (int d = 0; d < D; ++d) {
    const double ratio = size[d] / h;
    if (ratio < 0.5)
      g.fail_at("cell_size", fmt::format("cell_size {} is larger than the grid size {} along {}", h, size[d],
                                         axis_name(d)));
    if (ratio > kMaxCells + 0.5)
      g.fail_at("cell_size", fmt::format("gives {:.0f} cells along {}; at most {} are allowed", ratio,
                                         axis_name(d), kMaxCells));
    const double n = std::round(ratio);
    if (std::abs(n * h - size[d]) > 1e-9 * size[d])
      g.fail_at("size", fmt::format("the {} extent {} is not a whole multiple of cell_size {} "
                                    "({} cells)",
                                    axis_name(d), size[d], h, ratio));
    s.cells[static_cast<std::size_t>(d)] = static_cast<int>(n);
  }
  s.cell_size = h;
  if constexpr (D == 3) {
    if (g.has("geometry"))
      g.fail_at("geometry",
                "2D only: a 3D grid ([grid] size with 3 components) is neither plane strain nor "
                "axisymmetric");
  } else {
    s.geometry = g.choice<Geometry>(
        "geometry", {{"plane-strain", Geometry::PlaneStrain}, {"axisymmetric", Geometry::Axisymmetric}},
        Geometry::PlaneStrain);
    if (s.geometry == Geometry::Axisymmetric && s.origin[0] < 0.0)
      g.fail_at("origin", fmt::format("in axisymmetric geometry x is the radius r: the grid must start at "
                                      "x >= 0, got origin x = {}",
                                      s.origin[0]));
  }
}

// A body's point lattice turned about a centre (2D; Acosta §6, fig. 19).
template <int D>
void parse_lattice(const TableReader& t, const ScenarioOf<D>& s, BodyOf<D>& b) {
  if (!t.has("lattice_rotation") && !t.has("lattice_centre")) return;
  if constexpr (D == 3) {
    t.fail_at(t.has("lattice_rotation") ? "lattice_rotation" : "lattice_centre",
              "a turned point lattice is 2D only");
  } else {
    if (!t.has("lattice_rotation")) t.fail_at("lattice_centre", "needs lattice_rotation");
    b.lattice_rotation = t.number("lattice_rotation") * M_PI / 180.0;
    b.lattice_centre = t.vec_or<D>("lattice_centre", s.origin);
  }
}

template <int D>
void parse_bodies(const TableReader& root, ScenarioOf<D>& s) {
  const auto tables = root.array_of_tables("body");
  if (tables.empty()) fail(s.source, root.where("body"), "body", "at least one [[body]] table is required");
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const TableReader& t = tables[i];
    BodyOf<D> b;
    if constexpr (D == 2)
      b.shape = parse_shape2(t, s);
    else
      b.shape = parse_shape3(t, s);
    b.name = t.string("name", fmt::format("body-{}", i));
    b.material = material_index(t, "material", s);
    b.particles_per_cell = static_cast<int>(t.integer("particles_per_cell"));
    b.velocity = t.vec_or<D>("velocity", Vec<D>::Zero());
    parse_lattice(t, s, b);
    b.split = t.boolean_or("split", false);
    b.rigid = t.boolean_or("rigid", false);  // a contact partner with the constant `velocity`
    if (const auto vs = t.table("velocity_sine", false)) {
      vs->allow_declared();
      b.velocity_sine.amplitude = vs->vec<D>("amplitude");
      b.velocity_sine.wavelength = vs->number("wavelength");
      b.velocity_sine.axis = vs->choice<int>("axis", {{"x", 0}, {"y", 1}, {"z", 2}}, 0);
      if (b.velocity_sine.axis >= D) vs->fail_at("axis", "\"z\" needs a 3D grid");
      b.velocity_sine.origin = vs->number("origin");
    }
    if (!has_points(s, b))
      t.fail_at("shape", fmt::format("body \"{}\" contains no material point: it covers no "
                                     "sub-cell centre (spacing {} m); enlarge it, refine the grid "
                                     "or raise particles_per_cell",
                                     b.name, s.cell_size / b.particles_per_cell));
    if constexpr (D == 2)  // inside the grid, which starts at r >= 0 (parse_grid)
      if (s.geometry == Geometry::Axisymmetric && bounding_box(b.shape).lo[0] < -grid_tolerance(s))
        t.fail_at("shape", fmt::format("body \"{}\" reaches x = {} < 0; in axisymmetric geometry x is the "
                                       "radius r >= 0",
                                       b.name, bounding_box(b.shape).lo[0]));
    s.bodies.push_back(std::move(b));
  }
}

template <int D>
void parse_gravity(const TableReader& root, ScenarioOf<D>& s) {
  const auto g = root.table("gravity", false);
  if (!g) return;
  g->allow_declared();
  s.gravity = g->vec_or<D>("acceleration", Vec<D>::Zero());
  s.gravity_ramp_time = g->number("ramp_time");
}

namespace {

BoundarySide parse_side(const TableReader& bt, std::string_view side) {
  constexpr const char* allowed = "\"free\", \"fixed\", \"roller\", { type = \"friction\", friction = MU }";
  const toml::node& n = *bt.find(side);
  if (n.is_string()) {
    const Choices<BoundaryKind> choices = {
        {"free", BoundaryKind::Free}, {"fixed", BoundaryKind::Fixed}, {"roller", BoundaryKind::Roller}};
    const std::string v = bt.string(side);
    if (v == to_string(BoundaryKind::Friction))
      bt.fail_at(side,
                 "\"friction\" needs a coefficient: write { type = \"friction\", "
                 "friction = 0.6 }");
    for (const auto& [name, kind] : choices)
      if (v == name) return BoundarySide{kind, 0.0};
    bt.fail_at(side, fmt::format("unknown value \"{}\"; allowed values: {}", v, allowed));
  }
  if (!n.is_table()) bt.fail_type(side, "a string or an inline table { type = ... }");
  const TableReader t = bt.table(side, true)->follows("boundary.side");
  const BoundaryKind kind = t.choice<BoundaryKind>("type", {{"free", BoundaryKind::Free},
                                                            {"fixed", BoundaryKind::Fixed},
                                                            {"roller", BoundaryKind::Roller},
                                                            {"friction", BoundaryKind::Friction}});
  if (kind != BoundaryKind::Friction) {
    if (t.has("friction")) t.fail_at("friction", "only allowed together with type = \"friction\"");
    t.allow_only({"type"});
    return BoundarySide{kind, 0.0};
  }
  t.allow_declared();
  return BoundarySide{kind, t.number("friction")};
}

}  // namespace

template <int D>
void parse_boundary(const TableReader& root, ScenarioOf<D>& s) {
  const auto b = root.table("boundary", false);
  if (!b) return;
  if constexpr (D == 2)
    b->allow_only({"x_min", "x_max", "y_min", "y_max"});
  else
    b->allow_declared();
  const char* sides[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
  for (std::size_t k = 0; k < 2 * D; ++k)
    if (b->has(sides[k])) s.boundaries[k] = parse_side(*b, sides[k]);
}

template void parse_grid<2>(const TableReader&, Scenario&);
template void parse_grid<3>(const TableReader&, Scenario3&);
template void parse_bodies<2>(const TableReader&, Scenario&);
template void parse_bodies<3>(const TableReader&, Scenario3&);
template void parse_gravity<2>(const TableReader&, Scenario&);
template void parse_gravity<3>(const TableReader&, Scenario3&);
template void parse_boundary<2>(const TableReader&, Scenario&);
template void parse_boundary<3>(const TableReader&, Scenario3&);

}  // namespace skred::scenario_detail
