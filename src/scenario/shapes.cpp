// Point-in-shape tests and bounding boxes of the body shapes (2D and 3D).
#include <cmath>
#include <type_traits>

#include "scenario/build.hpp"

namespace skred {

namespace {

// Crossing number: count edges crossed by the ray from x towards +x. An edge covers the
// half-open span [low y, high y); evaluating it from its low end makes the intersection
// bit-identical for two polygons that share the edge in opposite directions.
bool polygon_contains(const Polygon& poly, const Vec<2>& x) {
  const auto& v = poly.vertices;
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

ShapeBox<2> polygon_box(const Polygon& p) {
  ShapeBox<2> b{Vec<2>::Constant(INFINITY), Vec<2>::Constant(-INFINITY)};
  for (const auto& v : p.vertices) {
    b.lo = b.lo.cwiseMin(v);
    b.hi = b.hi.cwiseMax(v);
  }
  return b;
}

}  // namespace

bool shape_contains(const Shape& shape, const Vec<2>& x) {
  if (const auto* r = std::get_if<Rectangle>(&shape))
    return x[0] >= r->min[0] && x[0] < r->max[0] && x[1] >= r->min[1] && x[1] < r->max[1];
  if (const auto* c = std::get_if<Disc>(&shape)) return (x - c->center).squaredNorm() < c->radius * c->radius;
  return polygon_contains(std::get<Polygon>(shape), x);
}

bool shape_contains(const Shape3& shape, const Vec<3>& x) {
  if (const auto* r = std::get_if<Box>(&shape))
    return (x.array() >= r->min.array()).all() && (x.array() < r->max.array()).all();
  if (const auto* c = std::get_if<Sphere>(&shape))
    return (x - c->center).squaredNorm() < c->radius * c->radius;
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    const Vec<3> r = x - c->center;
    const double t = r.dot(c->axis);  // along the axis
    return std::abs(t) < 0.5 * c->length && (r - t * c->axis).squaredNorm() < c->radius * c->radius;
  }
  const auto& e = std::get<ExtrudedPolygon>(shape);
  return x[2] >= e.z_min && x[2] < e.z_max && polygon_contains(e.section, x.head<2>());
}

ShapeBox<2> bounding_box(const Shape& shape) {
  if (const auto* r = std::get_if<Rectangle>(&shape)) return {r->min, r->max};
  if (const auto* c = std::get_if<Disc>(&shape)) {
    const Vec<2> r = Vec<2>::Constant(c->radius);
    return {c->center - r, c->center + r};
  }
  return polygon_box(std::get<Polygon>(shape));
}

ShapeBox<3> bounding_box(const Shape3& shape) {
  if (const auto* r = std::get_if<Box>(&shape)) return {r->min, r->max};
  if (const auto* c = std::get_if<Sphere>(&shape)) {
    const Vec<3> r = Vec<3>::Constant(c->radius);
    return {c->center - r, c->center + r};
  }
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    Vec<3> half;  // |a_d| L/2 + r sqrt(1 - a_d^2) along each axis
    for (int d = 0; d < 3; ++d)
      half[d] = std::abs(c->axis[d]) * 0.5 * c->length +
                c->radius * std::sqrt(std::max(0.0, 1.0 - c->axis[d] * c->axis[d]));
    return {c->center - half, c->center + half};
  }
  const auto& e = std::get<ExtrudedPolygon>(shape);
  const ShapeBox<2> b = polygon_box(e.section);
  return {Vec<3>(b.lo[0], b.lo[1], e.z_min), Vec<3>(b.hi[0], b.hi[1], e.z_max)};
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

}  // namespace skred
