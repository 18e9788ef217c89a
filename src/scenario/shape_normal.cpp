// The outward unit normal of a shape at a point: the gradient of the signed distance to its
// outline. A fixed rigid body's contact normal comes from it (Paper III §C.2.7: the master's
// normal defines the interface; docs/method.md, "Contact").
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "scenario/build.hpp"

namespace skred {

namespace {

// The closed polygon v (either orientation): outside it the unit vector from the nearest
// point of the outline to x (the outline's normal off an edge, turning round a corner);
// inside the outward normal of the nearest edge.
Vec<2> polygon_normal(const std::vector<Vec<2>>& v, const Vec<2>& x, bool inside) {
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
  return normal;
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
  return Vec<2>::Zero();  // a layer: no outline normal
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
  return Vec<3>::Zero();  // a cylinder, an extruded polygon: no outline normal here
}

}  // namespace skred
