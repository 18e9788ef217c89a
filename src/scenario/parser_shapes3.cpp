// The [[body]] shapes of a 3D scenario: box, polygon (extruded along z), cylinder, sphere, layer
// (from rasters, parser_ground3.cpp).
// docs/scenario.md documents their keys.
#include <cmath>

#include "scenario/parser_detail.hpp"

namespace skred::scenario_detail {

namespace {

Shape3 parse_box(const TableReader& b, const Scenario3& s) {
  Box r{b.vec<3>("min"), b.vec<3>("max")};
  if (!(r.max.array() > r.min.array()).all())
    b.fail_at("max", fmt::format("max {} must exceed min {} in every component", point_text<3>(r.max),
                                 point_text<3>(r.min)));
  check_inside(b, "min", s, r.min, "min corner");
  check_inside(b, "max", s, r.max, "max corner");
  return r;
}

Shape3 parse_extruded(const TableReader& b, const Scenario3& s) {
  const Vec<3> hi = grid_high(s);
  const double tol = grid_tolerance(s);
  ExtrudedPolygon e;
  e.section =
      parse_vertices(b, s.origin.head<2>(), hi.head<2>(), tol,
                     fmt::format("[{}, {}] x [{}, {}] (x-y)", s.origin[0], hi[0], s.origin[1], hi[1]));
  e.z_min = b.number("z_min");
  e.z_max = b.number("z_max");
  if (e.z_min < s.origin[2] - tol || e.z_min > hi[2] + tol)
    b.fail_at("z_min",
              fmt::format("z_min {} lies outside the grid's z range [{}, {}]", e.z_min, s.origin[2], hi[2]));
  if (!(e.z_max > e.z_min))
    b.fail_at("z_max", fmt::format("z_max {} must exceed z_min {}", e.z_max, e.z_min));
  if (e.z_max > hi[2] + tol)
    b.fail_at("z_max",
              fmt::format("z_max {} lies outside the grid's z range [{}, {}]", e.z_max, s.origin[2], hi[2]));
  return e;
}

Shape3 parse_cylinder(const TableReader& b, const Scenario3& s) {
  Cylinder c;
  c.center = b.vec<3>("center");
  c.axis = b.vec_or<3>("axis", Vec<3>::UnitY());
  if (!(c.axis.norm() > 0.0)) b.fail_at("axis", "the axis direction must not be zero");
  c.axis.normalize();
  c.radius = b.number("radius");
  c.length = b.number("length");
  check_inside(b, "center", s, c.center, "centre");
  // Half extent of the cylinder along each axis: |a_d| L/2 + r sqrt(1 - a_d^2).
  Vec<3> half;
  for (int d = 0; d < 3; ++d)
    half[d] = std::abs(c.axis[d]) * 0.5 * c.length +
              c.radius * std::sqrt(std::max(0.0, 1.0 - c.axis[d] * c.axis[d]));
  if (!inside_grid(s, Vec<3>(c.center - half)) || !inside_grid(s, Vec<3>(c.center + half)))
    b.fail_at(b.has("length") ? "length" : "radius",
              fmt::format("the cylinder of radius {} and length {} around {} extends outside the "
                          "grid {}",
                          c.radius, c.length, point_text<3>(c.center), grid_bounds(s)));
  return c;
}

Shape3 parse_sphere(const TableReader& b, const Scenario3& s) {
  Sphere c{b.vec<3>("center"), b.number("radius")};
  check_inside(b, "center", s, c.center, "centre");
  const Vec<3> r = Vec<3>::Constant(c.radius);
  if (!inside_grid(s, Vec<3>(c.center - r)) || !inside_grid(s, Vec<3>(c.center + r)))
    b.fail_at("radius", fmt::format("the sphere of radius {} around {} extends outside the grid {}", c.radius,
                                    point_text<3>(c.center), grid_bounds(s)));
  return c;
}

}  // namespace

Shape3 parse_shape3(const TableReader& t, const Scenario3& s) {
  enum class Kind { Box, Polygon, Cylinder, Sphere, Layer };
  const Kind kind = t.choice<Kind>("shape", {{"box", Kind::Box},
                                             {"polygon", Kind::Polygon},
                                             {"cylinder", Kind::Cylinder},
                                             {"sphere", Kind::Sphere},
                                             {"layer", Kind::Layer}});
  const char* section = kind == Kind::Box        ? "body (box)"
                        : kind == Kind::Polygon  ? "body (extruded polygon)"
                        : kind == Kind::Cylinder ? "body (cylinder)"
                        : kind == Kind::Layer    ? "body (layer)"
                                                 : "body (sphere)";
  t.allow_declared(&schema::section(section));
  const TableReader shape = t.follows(section);
  switch (kind) {
    case Kind::Box: return parse_box(shape, s);
    case Kind::Polygon: return parse_extruded(shape, s);
    case Kind::Cylinder: return parse_cylinder(shape, s);
    case Kind::Layer: return parse_layer3(shape, s);
    case Kind::Sphere: break;
  }
  return parse_sphere(shape, s);
}

}  // namespace skred::scenario_detail
