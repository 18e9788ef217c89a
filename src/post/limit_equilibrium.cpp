#include "post/limit_equilibrium.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace skred {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kSlices = 60;  // as bishop_factor's default

double arc_y(const SlipCircle& c, double x) {  // the circle's lower arc
  const double d = x - c.xc;
  return c.yc - std::sqrt(std::max(0.0, c.radius * c.radius - d * d));
}

// True where the arc runs under the ground's surface.
bool inside(const GroundProfile& g, const SlipCircle& c, double x) {
  const double top = g.surface(x);
  return std::isfinite(top) && arc_y(c, x) < top;
}

// The end of the run of `inside` between x_in (inside) and x_out (not), by bisection.
double crossing(const GroundProfile& g, const SlipCircle& c, double x_in, double x_out) {
  for (int k = 0; k < 40; ++k) {
    const double m = 0.5 * (x_in + x_out);
    (inside(g, c, m) ? x_in : x_out) = m;
  }
  return x_in;
}

// The x range where the arc cuts the ground, if it does so in one piece away from the ground's
// ends (a circle leaving through the side of the domain is not a mechanism of this ground).
bool slip_range(const GroundProfile& g, const SlipCircle& c, double& xa, double& xb) {
  const double lo = std::max(g.x0, c.xc - c.radius), hi = std::min(g.x_end(), c.xc + c.radius);
  if (!(hi > lo)) return false;
  constexpr int kSamples = 160;
  const double dx = (hi - lo) / kSamples;
  int first = -1, last = -1, runs = 0;
  bool was = false;
  for (int k = 0; k <= kSamples; ++k) {
    const bool in = inside(g, c, lo + k * dx);
    if (in && !was) ++runs;
    if (in) last = k, first = first < 0 ? k : first;
    was = in;
  }
  // One piece, and the arc comes up to the surface at both ends: an end still under the ground
  // (the circle's centre lies below the surface there) would need a cut the circle does not make.
  if (runs != 1 || (first == 0 && lo > g.x0) || (last == kSamples && hi < g.x_end())) return false;
  const double edge = 1e-9 * (g.x_end() - g.x0);
  xa = first == 0 ? lo : crossing(g, c, lo + first * dx, lo + (first - 1) * dx);
  xb = last == kSamples ? hi : crossing(g, c, lo + last * dx, lo + (last + 1) * dx);
  if ((xa <= g.x0 + edge && std::isfinite(g.surface(g.x0))) ||
      (xb >= g.x_end() - edge && std::isfinite(g.surface(g.x_end() - edge))))
    return false;
  return xb > xa;
}

// The ground prepared for many circles: per cell of the columns the unit weight (rows above a
// column's top soil take its weight, as the surface joined between column centres may rise into
// them) and its integral from row0 to the cell's bottom, so a slice's weight is two lookups.
class Ground {
 public:
  Ground(const GroundProfile& g, const std::vector<SoilStrength>& soils) : g_(g), soils_(soils) {
    const std::size_t n = g.top.size();
    layered_ = g.rows > 0;
    rows_ = layered_ ? g.rows : 1;
    row0_ = layered_ ? g.row0 : g.base;
    dy_ = layered_ ? g.row_height : 1.0;
    gamma_.assign(n * rows_, 0.0), below_.assign(n * rows_, 0.0);
    for (std::size_t j = 0; j < n; ++j) {
      int top = rows_ - 1;  // the column's top soil, whose weight carries up past it
      while (layered_ && top > 0 && g.soil[j * rows_ + top] == GroundProfile::kNoSoil) --top;
      double weight = 0.0, sum = 0.0;
      for (int k = 0; k < rows_; ++k) {
        const std::size_t at = j * rows_ + k;
        if (!layered_)
          weight = soils.front().unit_weight;
        else if (k <= top)
          weight = g.soil[at] >= 0 ? soils[g.soil[at]].unit_weight : 0.0;
        gamma_[at] = weight, below_[at] = sum;
        sum += weight * dy_;
      }
    }
  }

  std::size_t column(double x) const {
    const double u = std::floor((x - g_.x0) / g_.width);
    return static_cast<std::size_t>(std::clamp(u, 0.0, static_cast<double>(g_.top.size() - 1)));
  }
  // The weight per unit area of the ground between heights y and top in column j.
  double weight(std::size_t j, double y, double top) const { return load(j, top) - load(j, y); }
  // The soil at height y in column j (the nearest soil above, else below, in an empty cell);
  // nullptr if the column has none.
  const SoilStrength* soil(std::size_t j, double y) const {
    if (!layered_) return &soils_.front();
    const int k = row(y);
    for (int u = k; u < rows_; ++u)
      if (const int i = g_.soil[j * rows_ + u]; i >= 0) return &soils_[i];
    for (int u = k - 1; u >= 0; --u)
      if (const int i = g_.soil[j * rows_ + u]; i >= 0) return &soils_[i];
    return nullptr;
  }

 private:
  int row(double y) const {
    return static_cast<int>(std::clamp(std::floor((y - row0_) / dy_), 0.0, rows_ - 1.0));
  }
  double load(std::size_t j, double y) const {
    const int k = row(y);
    const std::size_t at = j * rows_ + k;
    return below_[at] + gamma_[at] * (y - (row0_ + k * dy_));
  }
  const GroundProfile& g_;
  const std::vector<SoilStrength>& soils_;
  bool layered_ = false;
  int rows_ = 1;
  double row0_ = 0.0, dy_ = 1.0;
  std::vector<double> gamma_, below_;
};

double bishop(const Ground& ground, const GroundProfile& g, const SlipCircle& c, int direction, int slices) {
  double xa = 0.0, xb = 0.0;
  if (!slip_range(g, c, xa, xb)) return kNaN;
  const double b = (xb - xa) / slices;
  double drive = 0.0, fellenius = 0.0;
  thread_local std::vector<double> weight, sin_a, cos_a, bond, tan_phi;
  for (auto* v : {&weight, &sin_a, &cos_a, &bond, &tan_phi}) v->assign(slices, 0.0);
  auto angle = [&](double x) { return std::asin(std::clamp((x - c.xc) / c.radius, -1.0, 1.0)); };
  double deepest = 0.0;
  for (int i = 0; i < slices; ++i) {
    const double x = xa + (i + 0.5) * b, y = arc_y(c, x);
    if (y < g.base) return kNaN;  // the slip surface may not cut the firm base
    deepest = std::max(deepest, g.surface(x) - y);
    const std::size_t j = ground.column(x);
    const SoilStrength* s = ground.soil(j, y);
    if (!s || s->firm) return kNaN;  // nor material that does not yield
    weight[i] = b * std::max(0.0, ground.weight(j, y, g.surface(x)));
    tan_phi[i] = std::tan(s->friction);
    sin_a[i] = direction * (c.xc - x) / c.radius;  // the base's inclination, down towards the motion
    cos_a[i] = (c.yc - y) / c.radius;
    // c l cos(alpha), l the slice's arc length taken exactly (c b at the midpoint's alpha
    // underrates a steep scarp's length)
    bond[i] = s->cohesion * c.radius * (angle(x + 0.5 * b) - angle(x - 0.5 * b)) * cos_a[i];
    drive += weight[i] * sin_a[i];
    fellenius += bond[i] / cos_a[i] + weight[i] * cos_a[i] * tan_phi[i];
  }
  if (!(drive > 0.0) || deepest < g.min_depth) return kNaN;
  double F = fellenius / drive;  // the ordinary method's F starts Bishop's iteration
  for (int it = 0; it < 200; ++it) {
    double resist = 0.0;
    for (int i = 0; i < slices; ++i) {
      const double m = cos_a[i] + sin_a[i] * tan_phi[i] / F;  // Bishop's m_alpha
      if (m <= 0.0 || (sin_a[i] < 0.0 && m <= 0.2)) return kNaN;
      resist += (bond[i] + weight[i] * tan_phi[i]) / m;
    }
    const double next = resist / drive;
    if (std::abs(next - F) <= 1e-10 * F) return next;
    F = next;
  }
  return F;
}

bool valid(const GroundProfile& g, const std::vector<SoilStrength>& soils) {
  if (soils.empty() || g.top.empty()) return false;
  if (g.rows == 0) return true;
  if (!(g.row_height > 0.0) || g.soil.size() != g.top.size() * static_cast<std::size_t>(g.rows)) return false;
  return std::all_of(g.soil.begin(), g.soil.end(), [&](int i) {
    return i == GroundProfile::kNoSoil || (i >= 0 && static_cast<std::size_t>(i) < soils.size());
  });
}

}  // namespace

double GroundProfile::surface(double x) const {
  const double u = (x - x0) / width;
  const long n = static_cast<long>(top.size());
  const long j = static_cast<long>(std::floor(u));
  if (j < 0 || j >= n || !std::isfinite(top[j])) return kNaN;
  const double t = u - static_cast<double>(j) - 0.5;
  const long k = t < 0.0 ? j - 1 : j + 1;
  if (k < 0 || k >= n || !std::isfinite(top[k])) return top[j];
  return top[j] + std::abs(t) * (top[k] - top[j]);
}

double bishop_factor(const GroundProfile& g, const std::vector<SoilStrength>& soils, const SlipCircle& c,
                     int direction, int slices) {
  if (!valid(g, soils) || slices < 1) return kNaN;
  return bishop(Ground(g, soils), g, c, direction, slices);
}

double bishop_factor(const GroundProfile& g, const SoilStrength& s, const SlipCircle& c, int direction,
                     int slices) {
  return bishop_factor(g, std::vector<SoilStrength>{s}, c, direction, slices);
}

CriticalCircle critical_circle(const GroundProfile& g, const SoilStrength& s) {
  return critical_circle(g, std::vector<SoilStrength>{s});
}

CriticalCircle critical_circle(const GroundProfile& g, const std::vector<SoilStrength>& soils) {
  CriticalCircle best{std::numeric_limits<double>::infinity(), {}, 1};
  if (!valid(g, soils)) return best;
  const Ground ground(g, soils);
  double x_first = INFINITY, x_last = -INFINITY, y_top = -INFINITY;
  for (std::size_t j = 0; j < g.top.size(); ++j) {
    if (!std::isfinite(g.top[j])) continue;
    x_first = std::min(x_first, g.x0 + g.width * static_cast<double>(j));
    x_last = std::max(x_last, g.x0 + g.width * static_cast<double>(j + 1));
    y_top = std::max(y_top, g.top[j]);
  }
  const double height = y_top - g.base;
  if (!(x_last > x_first) || !(height > 0.0)) return best;
  auto trial = [&](const SlipCircle& c) {
    for (int dir : {1, -1}) {
      const double F = bishop(ground, g, c, dir, kSlices);
      if (F < best.factor) best = {F, c, dir};
    }
  };
  // Centres over the ground's length and a height beyond each end, from half its height above
  // the base to two and a half heights above it; the circle's lowest point from twice the height below the
  // base (a circle whose bottom lies beyond a face, in the air) to the top.
  constexpr int kN = 30;
  for (int i = 0; i <= kN; ++i)
    for (int k = 0; k <= kN; ++k) {
      const double xc = x_first - height + (x_last - x_first + 2.0 * height) * i / kN;
      const double yc = g.base + 0.5 * height + 2.5 * height * k / kN;
      for (int r = 0; r < kN; ++r) {
        const double y_low = g.base - 2.0 * height + 3.0 * height * r / kN;
        if (yc - y_low > 0.0) trial({xc, yc, yc - y_low});
      }
    }
  if (!std::isfinite(best.factor)) return best;
  // Pattern search: move the centre or the radius by `step` while F falls, then halve the step.
  for (double step = std::max(x_last - x_first, height) / kN; step > g.width / 200.0;) {
    const CriticalCircle before = best;
    const SlipCircle c = best.circle;
    for (const SlipCircle& n :
         {SlipCircle{c.xc + step, c.yc, c.radius}, SlipCircle{c.xc - step, c.yc, c.radius},
          SlipCircle{c.xc, c.yc + step, c.radius}, SlipCircle{c.xc, c.yc - step, c.radius},
          SlipCircle{c.xc, c.yc, c.radius + step}, SlipCircle{c.xc, c.yc, c.radius - step},
          SlipCircle{c.xc, c.yc + step, c.radius + step}, SlipCircle{c.xc, c.yc - step, c.radius - step}})
      if (n.radius > 0.0) trial(n);
    if (!(best.factor < before.factor)) step *= 0.5;
  }
  slip_range(g, best.circle, best.x_from, best.x_to);
  return best;
}

}  // namespace skred
