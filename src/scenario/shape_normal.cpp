// The outward unit normal of a shape at a point: the gradient of the signed distance to its
// outline. A fixed rigid body's contact normal comes from it (Paper III §C.2.7: the master's
// normal defines the interface; docs/method.md, "Contact").
#include <algorithm>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <limits>
#include <vector>

#include "scenario/build.hpp"

namespace skred {

namespace {

// The closed polygon v (either orientation): outside it the unit vector from the nearest
// point of the outline to x (the outline's normal off an edge, turning round a corner);
// inside the outward normal of the nearest edge. `distance`, if given, gets x's distance to
// the outline.
Vec<2> polygon_normal(const std::vector<Vec<2>>& v, const Vec<2>& x, bool inside,
                      double* distance = nullptr) {
  const std::size_t m = v.size();
  double area2 = 0.0;
  for (std::size_t k = 0; k < m; ++k) area2 += v[k][0] * v[(k + 1) % m][1] - v[(k + 1) % m][0] * v[k][1];
  const double turn = area2 > 0.0 ? 1.0 : -1.0;  // counter-clockwise: the outside is on the right
  double best = std::numeric_limits<double>::infinity();
  Vec<2> normal = Vec<2>::Zero();
  for (std::size_t k = 0; k < m; ++k) {
    const Vec<2> a = v[k], e = v[(k + 1) % m] - a;
    const double len2 = e.squaredNorm();
    if (!(len2 > 0.0)) continue;
    const double s = std::clamp((x - a).dot(e) / len2, 0.0, 1.0);
    const Vec<2> r = x - (a + s * e);
    const double d2 = r.squaredNorm();
    if (!(d2 < best)) continue;
    best = d2;
    const Vec<2> edge = turn * Vec<2>(e[1], -e[0]) / std::sqrt(len2);
    normal = inside || !(d2 > 1e-24 * len2) ? edge : Vec<2>(r / std::sqrt(d2));
  }
  if (distance) *distance = std::sqrt(best);
  return normal;
}

// A layer's outline (Layer: bottom(x) <= y < min(top(x), surface(x)) over the x span of its
// profiles) as a polygon: the bottom profile left to right, then the lower of top and
// surface right to left, with the points where those two cross.
std::vector<Vec<2>> layer_outline(const Layer& l) {
  double lo = std::max(l.top.points.front()[0], l.bottom.points.front()[0]);
  double hi = std::min(l.top.points.back()[0], l.bottom.points.back()[0]);
  if (l.surface)
    lo = std::max(lo, l.surface->points.front()[0]), hi = std::min(hi, l.surface->points.back()[0]);
  const auto upper = [&](double x) {
    return l.surface ? std::min(l.top.at(x), l.surface->at(x)) : l.top.at(x);
  };
  const auto xs_of = [&](std::initializer_list<const Profile*> profiles) {
    std::vector<double> xs{lo, hi};
    for (const Profile* p : profiles)
      for (const Vec<2>& q : p->points)
        if (q[0] > lo && q[0] < hi) xs.push_back(q[0]);
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    return xs;
  };
  std::vector<Vec<2>> v;
  for (double x : xs_of({&l.bottom})) v.emplace_back(x, l.bottom.at(x));
  std::vector<double> xs = l.surface ? xs_of({&l.top, &*l.surface}) : xs_of({&l.top});
  if (l.surface)  // where top and surface cross between two abscissae, both are linear
    for (std::size_t k = 0, n = xs.size(); k + 1 < n; ++k) {
      const double a = l.top.at(xs[k]) - l.surface->at(xs[k]),
                   b = l.top.at(xs[k + 1]) - l.surface->at(xs[k + 1]);
      if (a * b < 0.0) xs.push_back(xs[k] + (xs[k + 1] - xs[k]) * a / (a - b));
    }
  std::sort(xs.begin(), xs.end(), std::greater<>());
  for (double x : xs) v.emplace_back(x, upper(x));
  return v;
}

// Outward normal from the distances outside (> 0) or inside (< 0) two families of faces
// meeting at right angles, with their unit normals n1, n2: inside, the nearer face's; outside
// one, that face's; outside both, from the nearest edge.
Vec<3> right_angle_normal(double d1, const Vec<3>& n1, double d2, const Vec<3>& n2) {
  if (d1 > 0.0 && d2 > 0.0) return (d1 * n1 + d2 * n2).normalized();
  if (d1 > 0.0) return n1;
  if (d2 > 0.0) return n2;
  return d1 > d2 ? n1 : n2;
}

std::vector<Vec<2>> corners(const Vec<2>& lo, const Vec<2>& hi) {
  return {lo, Vec<2>(hi[0], lo[1]), hi, Vec<2>(lo[0], hi[1])};
}

}  // namespace

Vec<2> shape_normal(const Shape& shape, const Vec<2>& x) {
  if (const auto* r = std::get_if<Rectangle>(&shape))
    return polygon_normal(corners(r->min, r->max), x, shape_contains(shape, x));
  if (const auto* p = std::get_if<Polygon>(&shape))
    return polygon_normal(p->vertices, x, shape_contains(shape, x));
  if (const auto* c = std::get_if<Disc>(&shape)) {
    const Vec<2> r = x - c->center;
    return r.norm() > 0.0 ? Vec<2>(r.normalized()) : Vec<2>::Zero();
  }
  const Layer& l = std::get<Layer>(shape);
  if (l.top.points.size() < 2 || l.bottom.points.size() < 2) return Vec<2>::Zero();  // no outline
  return polygon_normal(layer_outline(l), x, shape_contains(shape, x));
}

Vec<3> shape_normal(const Shape3& shape, const Vec<3>& x) {
  if (const auto* c = std::get_if<Sphere>(&shape)) {
    const Vec<3> r = x - c->center;
    return r.norm() > 0.0 ? Vec<3>(r.normalized()) : Vec<3>::Zero();
  }
  if (const auto* b = std::get_if<Box>(&shape)) {
    // Outside: from the nearest point of the box; inside: the nearest face's normal.
    const Vec<3> q = x.cwiseMax(b->min).cwiseMin(b->max), r = x - q;
    if (r.norm() > 0.0) return r.normalized();
    Vec<3> n = Vec<3>::Zero();
    double best = std::numeric_limits<double>::infinity();
    for (int d = 0; d < 3; ++d)
      for (int side = 0; side < 2; ++side) {
        const double dist = side ? b->max[d] - x[d] : x[d] - b->min[d];
        if (dist < best) best = dist, n = Vec<3>::Zero(), n[d] = side ? 1.0 : -1.0;
      }
    return n;
  }
  if (const auto* e = std::get_if<ExtrudedPolygon>(&shape)) {
    // The section's outline in x-y and the end faces in z, at right angles.
    const Vec<2> xy(x[0], x[1]);
    const bool in = shape_contains(Shape(e->section), xy);
    double d = 0.0;
    const Vec<2> n = polygon_normal(e->section.vertices, xy, in, &d);
    const double dz = std::max(e->z_min - x[2], x[2] - e->z_max);
    const Vec<3> nz(0.0, 0.0, x[2] - e->z_min < e->z_max - x[2] ? -1.0 : 1.0);
    return right_angle_normal(in ? -d : d, Vec<3>(n[0], n[1], 0.0), dz, nz);
  }
  if (std::holds_alternative<Layer3>(shape)) return Vec<3>::Zero();  // no outline here
  const auto& c = std::get<Cylinder>(shape);
  // The mantle (radial) and the end faces (along the axis), at right angles.
  const Vec<3> r = x - c.center;
  const double s = r.dot(c.axis);
  const Vec<3> radial = r - s * c.axis;
  const Vec<3> na = s < 0.0 ? Vec<3>(-c.axis) : c.axis;
  if (!(radial.norm() > 0.0)) return na;
  return right_angle_normal(radial.norm() - c.radius, radial.normalized(), std::abs(s) - 0.5 * c.length, na);
}

}  // namespace skred
