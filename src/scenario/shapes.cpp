// Point-in-shape tests and bounding boxes of the body shapes (2D and 3D).
#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

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

// The x range where every profile of the layer is defined: [lo, hi).
std::pair<double, double> layer_span(const Layer& l) {
  double lo = std::max(l.top.points.front()[0], l.bottom.points.front()[0]);
  double hi = std::min(l.top.points.back()[0], l.bottom.points.back()[0]);
  if (l.surface) {
    lo = std::max(lo, l.surface->points.front()[0]);
    hi = std::min(hi, l.surface->points.back()[0]);
  }
  return {lo, hi};
}

bool layer_contains(const Layer& l, const Vec<2>& x) {
  const auto [lo, hi] = layer_span(l);
  if (!(x[0] >= lo && x[0] < hi)) return false;
  return x[1] >= l.bottom.at(x[0]) && x[1] < l.top.at(x[0]) && (!l.surface || x[1] < l.surface->at(x[0]));
}

ShapeBox<2> layer_box(const Layer& l) {
  const auto [lo, hi] = layer_span(l);
  double y_lo = INFINITY, y_hi = -INFINITY;
  for (const auto& p : l.bottom.points) y_lo = std::min(y_lo, p[1]);
  for (const auto& p : l.top.points) y_hi = std::max(y_hi, p[1]);
  return {Vec<2>(lo, y_lo), Vec<2>(std::max(lo, hi), std::max(y_lo, y_hi))};
}

}  // namespace

double Profile::at(double x) const {
  const auto it =
      std::upper_bound(points.begin(), points.end(), x, [](double v, const Vec<2>& p) { return v < p[0]; });
  if (it == points.begin()) return points.front()[1];
  if (it == points.end()) return points.back()[1];
  const Vec<2>& a = *(it - 1);
  const Vec<2>& b = *it;
  return a[1] + (x - a[0]) * (b[1] - a[1]) / (b[0] - a[0]);
}

// Bilinear between the cell centres, the fractional cell clamped to them (constant across the
// outer half cells).
double ElevationRaster::at(double x, double z) const {
  const auto axis = [](double u, int n, int& i, int& i1, double& t) {
    u = std::clamp(u, 0.0, n - 1.0);
    i = std::min(static_cast<int>(u), std::max(n - 2, 0));
    i1 = std::min(i + 1, n - 1);
    t = u - i;
  };
  int i, i1, j, j1;
  double t, w;
  axis(to_cell[0] + to_cell[1] * x + to_cell[2] * z, columns, i, i1, t);
  axis(to_cell[3] + to_cell[4] * x + to_cell[5] * z, rows, j, j1, w);
  const auto h = [&](int a, int b) { return heights[static_cast<std::size_t>(b) * columns + a]; };
  return (1 - w) * ((1 - t) * h(i, j) + t * h(i1, j)) + w * ((1 - t) * h(i, j1) + t * h(i1, j1));
}

bool shape_contains(const Shape& shape, const Vec<2>& x) {
  if (const auto* r = std::get_if<Rectangle>(&shape))
    return x[0] >= r->min[0] && x[0] < r->max[0] && x[1] >= r->min[1] && x[1] < r->max[1];
  if (const auto* c = std::get_if<Disc>(&shape)) return (x - c->center).squaredNorm() < c->radius * c->radius;
  if (const auto* l = std::get_if<Layer>(&shape)) return layer_contains(*l, x);
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
  if (const auto* l = std::get_if<Layer3>(&shape)) {
    if (!((x.array() >= l->lo.array()).all() && (x.array() < l->hi.array()).all())) return false;
    return (!l->bottom || x[1] >= l->bottom->at(x[0], x[2])) && x[1] < l->top->at(x[0], x[2]) &&
           (!l->surface || x[1] < l->surface->at(x[0], x[2]));
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
  if (const auto* l = std::get_if<Layer>(&shape)) return layer_box(*l);
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
  if (const auto* l = std::get_if<Layer3>(&shape)) return {l->lo, l->hi};
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

double layer_area(const Layer& l) {
  const auto span = layer_span(l);
  const double lo = span.first, hi = span.second;  // (plain names: a lambda captures them)
  if (!(hi > lo)) return 0.0;
  // Between two consecutive profile points every profile is linear; min(top, surface) kinks
  // where they cross and max(0, thickness) where the thickness changes sign: split there
  // and integrate the linear pieces exactly.
  std::vector<double> xs = {lo, hi};
  const auto add = [&](const Profile& p) {
    for (const auto& q : p.points)
      if (q[0] > lo && q[0] < hi) xs.push_back(q[0]);
  };
  add(l.top), add(l.bottom);
  if (l.surface) add(*l.surface);
  std::sort(xs.begin(), xs.end());
  const auto upper = [&](double x) {
    return l.surface ? std::min(l.top.at(x), l.surface->at(x)) : l.top.at(x);
  };
  double area = 0.0;
  for (std::size_t k = 0; k + 1 < xs.size(); ++k) {
    std::vector<double> cut = {xs[k], xs[k + 1]};
    // Where top and surface cross, min() kinks; where the thickness changes sign, max() does.
    if (l.surface) {
      const double da = l.top.at(xs[k]) - l.surface->at(xs[k]);
      const double db = l.top.at(xs[k + 1]) - l.surface->at(xs[k + 1]);
      if (da * db < 0) cut.push_back(xs[k] + (xs[k + 1] - xs[k]) * da / (da - db));
    }
    std::sort(cut.begin(), cut.end());
    for (std::size_t j = 0; j + 1 < cut.size(); ++j) {
      const double a = cut[j], b = cut[j + 1];
      const double ta = upper(a) - l.bottom.at(a), tb = upper(b) - l.bottom.at(b);
      if (ta >= 0 && tb >= 0)
        area += 0.5 * (ta + tb) * (b - a);
      else if (ta > 0)
        area += 0.5 * ta * (b - a) * ta / (ta - tb);
      else if (tb > 0)
        area += 0.5 * tb * (b - a) * tb / (tb - ta);
    }
  }
  return area;
}

double layer_volume(const Layer3& l) {
  // The midpoint rule on 1024 x 1024 columns of the layer's horizontal extent.
  constexpr int n = 1024;
  const double dx = (l.hi[0] - l.lo[0]) / n, dz = (l.hi[2] - l.lo[2]) / n;
  double volume = 0.0;
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < n; ++i) {
      const double x = l.lo[0] + (i + 0.5) * dx, z = l.lo[2] + (k + 0.5) * dz;
      double top = std::min(l.top->at(x, z), l.hi[1]);
      if (l.surface) top = std::min(top, l.surface->at(x, z));
      volume += std::max(0.0, top - std::max(l.lo[1], l.bottom ? l.bottom->at(x, z) : l.lo[1]));
    }
  return volume * dx * dz;
}

}  // namespace skred
