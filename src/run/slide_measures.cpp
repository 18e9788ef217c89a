#include "run/slide_measures.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace skred {

namespace {

// A point's current half-size l0 det(F)^(1/d), as GIMP sizes its domain (Thesis eq. 3.23):
// the material a point stands for, not the corners of its voxel, so a voxel sheared into a
// needle does not reach metres beyond the material.
template <int D>
Vec<D> half_size(const Particles<D>& P, std::size_t p) {
  const double J = P.F[p].determinant();
  return P.half0[p] * std::pow(std::max(J, 0.0), 1.0 / D);
}

// Point p in the columns of a profile: the columns [first, last] its domain reaches along
// `axis`, its top and its edges along the axis.
struct PointSpan {
  int first, last;
  double top, lo, hi;
};
template <int D>
PointSpan point_span(const Particles<D>& P, std::size_t p, double x0, double width, int bins, int axis) {
  const Vec<D> r = half_size(P, p);
  const double lo = P.x[p][axis] - r[axis], hi = P.x[p][axis] + r[axis];
  return {std::max(0, static_cast<int>(std::floor((lo - x0) / width))),
          std::min(bins - 1, static_cast<int>(std::floor((hi - x0) / width))), P.x[p][1] + r[1], lo, hi};
}

// The level a column's deposit must stand above: its surface at the start (`floor` where it held
// no material) plus `threshold`.
double column_level(const SurfaceProfile& s, std::size_t b, double threshold, double floor) {
  return (std::isfinite(s.top[b]) ? s.top[b] : floor) + threshold;
}

}  // namespace

template <int D>
MaterialExtent material_extent(const Particles<D>& P, const Processes& procs) {
  double x_min = INFINITY, x_max = -INFINITY, y_min = INFINITY, y_max = -INFINITY;
  double z_min = D == 3 ? INFINITY : 0.0, z_max = D == 3 ? -INFINITY : 0.0;
  const long n = static_cast<long>(P.size());
#pragma omp parallel for reduction(min : x_min, y_min, z_min) reduction(max : x_max, y_max, z_max)
  for (long p = 0; p < n; ++p) {
    const Vec<D> r = half_size(P, static_cast<std::size_t>(p));
    x_min = std::min(x_min, P.x[p][0] - r[0]);
    x_max = std::max(x_max, P.x[p][0] + r[0]);
    y_min = std::min(y_min, P.x[p][1] - r[1]);
    y_max = std::max(y_max, P.x[p][1] + r[1]);
    if constexpr (D == 3) {
      z_min = std::min(z_min, P.x[p][2] - r[2]);
      z_max = std::max(z_max, P.x[p][2] + r[2]);
    }
  }
  double lo[] = {x_min, y_min, z_min}, hi[] = {x_max, y_max, z_max};
  procs.min(lo, 3);
  procs.max(hi, 3);
  const MaterialExtent e{lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]};
  return e;
}

template <int D>
StageTracker<D>::StageTracker(std::string name, Particles<D>& P, double time, double kinetic_energy,
                              double rest_speed, double rest_time, double x0, double width, double length,
                              double thickness, double z0, double z_length, const Processes& procs)
    : procs_(procs),
      start_(material_extent(P, procs)),
      kinetic_start_(kinetic_energy),
      rest_speed_(rest_speed),
      rest_time_(rest_time),
      threshold_(thickness > 0.0 ? thickness : 0.5 * width),
      floor_(thickness > 0.0 ? start_.y_min : -INFINITY),
      x0_(x0),
      width_(width),
      length_(length),
      z0_(z0),
      z_length_(z_length) {
  profile_ = start_profile(P, x0_, width_, bins(), threshold_, 0, floor_, procs_);
  if constexpr (D == 3) profile_z_ = start_profile(P, z0_, width_, bins_z(), threshold_, 2, floor_, procs_);
  m_.name = std::move(name);
  m_.start_time = time;
  m_.height_start = start_.y_max - start_.y_min;
  for (std::size_t p = 0; p < P.size(); ++p) P.plastic_ref[p] = P.state[p].plastic_shear_strain;
}

template <int D>
double StageTracker<D>::max_displacement(const Particles<D>& P, const Processes& procs) {
  double largest = 0.0;
  const long n = static_cast<long>(P.size());
#pragma omp parallel for reduction(max : largest) schedule(static)
  for (long p = 0; p < n; ++p) largest = std::max(largest, (P.x[p] - P.x_ref[p]).squaredNorm());
  procs.max(&largest, 1);
  return std::sqrt(largest);
}

template <int D>
void StageTracker<D>::record_speed(double time, double mean_speed) {
  if (mean_speed > m_.peak_mean_speed) {
    m_.peak_mean_speed = mean_speed;
    m_.peak_time = time - m_.start_time;
  }
  m_.final_mean_speed = mean_speed;
}

template <int D>
void StageTracker<D>::start_window(Particles<D>& P, double time) {
  P.x_rest = P.x;  // (its capacity is kept: no allocation after the first window)
  window_start_ = time;
}

template <int D>
bool StageTracker<D>::observe_window(Particles<D>& P, double time, double mean_speed) {
  record_speed(time, mean_speed);
  if (std::isnan(window_start_) || procs_.any(P.x_rest.size() != P.size())) {
    start_window(P, time);
    return false;
  }
  const double length = time - window_start_;
  if (length < rest_time_ * (1.0 - 1e-9) || length <= 0.0) return false;
  double moved = 0.0, mass = 0.0;
  const long n = static_cast<long>(P.size());
  for (long p = 0; p < n; ++p) {  // (once per window)
    moved += P.mass[p] * (P.x[p] - P.x_rest[p]).norm();
    mass += P.mass[p];
  }
  double sums[] = {moved, mass};
  procs_.sum(sums, 2);
  moved = sums[0], mass = sums[1];
  const double speed = mass > 0.0 ? moved / (mass * length) : 0.0;
  samples_.emplace_back(window_start_, speed);
  start_window(P, time);
  return rest_speed_ > 0.0 && speed < rest_speed_;
}

template <int D>
bool StageTracker<D>::observe(double time, double mean_speed, double rest_measure_speed) {
  record_speed(time, mean_speed);
  samples_.emplace_back(time, rest_measure_speed);
  if (rest_speed_ <= 0.0) return false;
  if (rest_measure_speed >= rest_speed_) {
    quiet_since_.reset();
    return false;
  }
  if (!quiet_since_) quiet_since_ = time;
  return time - *quiet_since_ >= rest_time_ * (1.0 - 1e-9);
}

template <int D>
SurfaceProfile surface_profile(const Particles<D>& P, double x0, double width, int bins, int axis,
                               const std::vector<double>& above, const Processes& procs) {
  const auto n = static_cast<std::size_t>(bins);
  SurfaceProfile s;
  s.top.assign(n, -INFINITY);
  s.lo.assign(n, INFINITY);
  s.hi.assign(n, -INFINITY);
  for (std::size_t p = 0; p < P.size(); ++p) {
    const PointSpan q = point_span(P, p, x0, width, bins, axis);
    for (int b = q.first; b <= q.last; ++b) {
      const auto k = static_cast<std::size_t>(b);
      s.top[k] = std::max(s.top[k], q.top);
      if (!above.empty() && !(q.top > above[k])) continue;
      s.lo[k] = std::min(s.lo[k], q.lo);
      s.hi[k] = std::max(s.hi[k], q.hi);
    }
  }
  procs.max(s.top.data(), n);
  procs.min(s.lo.data(), n);
  procs.max(s.hi.data(), n);
  return s;
}

template <int D>
SurfaceProfile start_profile(const Particles<D>& P, double x0, double width, int bins, double threshold,
                             int axis, double floor, const Processes& procs) {
  SurfaceProfile s = surface_profile(P, x0, width, bins, axis, {}, procs);
  const auto n = static_cast<std::size_t>(bins);
  const auto level = [&](int t) { return column_level(s, static_cast<std::size_t>(t), threshold, floor); };
  s.toe_hi.assign(n, -INFINITY);
  s.toe_lo.assign(n, INFINITY);
  // Per side (0: towards +x, 1: towards -x), the tips whose toe column is b: tips[first[b] ...
  // first[b + 1]) (a tip without a toe column is in none).
  std::vector<int> first[2], tips[2];
  for (int side = 0; side < 2; ++side) {
    const int dir = side == 0 ? 1 : -1;
    std::vector<int> toe(n, -1);
    first[side].assign(n + 1, 0);
    for (int t = 0; t < bins; ++t)
      for (int b = t - dir; b >= 0 && b < bins; b -= dir)
        if (s.top[static_cast<std::size_t>(b)] > level(t)) {
          toe[static_cast<std::size_t>(t)] = b;
          ++first[side][static_cast<std::size_t>(b) + 1];
          break;
        }
    for (std::size_t b = 0; b < n; ++b) first[side][b + 1] += first[side][b];
    tips[side].resize(static_cast<std::size_t>(first[side][n]));
    std::vector<int> fill(first[side].begin(), first[side].end() - 1);
    for (int t = 0; t < bins; ++t)
      if (const int b = toe[static_cast<std::size_t>(t)]; b >= 0)
        tips[side][static_cast<std::size_t>(fill[static_cast<std::size_t>(b)]++)] = t;
  }
  for (std::size_t p = 0; p < P.size(); ++p) {
    const PointSpan q = point_span(P, p, x0, width, bins, axis);
    for (int b = q.first; b <= q.last; ++b)
      for (int side = 0; side < 2; ++side) {
        const auto k = static_cast<std::size_t>(b);
        for (int i = first[side][k]; i < first[side][k + 1]; ++i) {
          const int t = tips[side][static_cast<std::size_t>(i)];
          if (!(q.top > level(t))) continue;
          double& toe =
              side == 0 ? s.toe_hi[static_cast<std::size_t>(t)] : s.toe_lo[static_cast<std::size_t>(t)];
          toe = side == 0 ? std::max(toe, q.hi) : std::min(toe, q.lo);
        }
      }
  }
  procs.max(s.toe_hi.data(), n);
  procs.min(s.toe_lo.data(), n);
  return s;
}

template <int D>
Runout runout_of(const SurfaceProfile& before, const Particles<D>& P, double x0, double width,
                 double threshold, int axis, double floor, const Processes& procs) {
  const int n = static_cast<int>(before.top.size());
  if (before.toe_hi.size() != before.top.size() || before.toe_lo.size() != before.top.size())
    throw std::invalid_argument(
        "runout_of: the profile at the start has no toes (make it with start_profile)");
  std::vector<double> level(before.top.size());
  for (std::size_t b = 0; b < level.size(); ++b) level[b] = column_level(before, b, threshold, floor);
  // after.lo/hi: the edges of the points that raise their column by more than `threshold`.
  const SurfaceProfile after = surface_profile(P, x0, width, n, axis, level, procs);
  Runout r;
  // The connected deposit: the run of columns holding material around the highest one (the
  // main mass). A point that has left it, across an empty column, moves no front.
  int peak = 0;
  for (int b = 1; b < n; ++b)
    if (after.top[b] > after.top[peak]) peak = b;
  int first = peak, last = peak;
  while (first > 0 && std::isfinite(after.top[first - 1])) --first;
  while (last < n - 1 && std::isfinite(after.top[last + 1])) ++last;
  // Over a base layer every column holds material, so the deposit is also cut where the slide
  // left a column unraised: of the runs of raised columns within [first, last] that reach a side
  // of the highest column, the deposit on that side is the widest (of equal ones the outer), and
  // a clump that came to rest beyond a column the slide left bare is a run of its own that moves
  // no front. Its outer end is the tip column: tips[0] towards +x, tips[1] towards -x.
  const auto raised = [&](int b) { return after.top[b] > level[b]; };
  int tips[2] = {-1, -1}, widest[2] = {0, 0};
  for (int b = first; b <= last;) {
    if (!raised(b)) {
      ++b;
      continue;
    }
    int e = b;
    while (e < last && raised(e + 1)) ++e;
    const int w = e - b + 1;
    if (e >= peak && w >= widest[0]) widest[0] = w, tips[0] = e;  // runs come inner to outer
    if (b <= peak && w > widest[1]) widest[1] = w, tips[1] = b;   // runs come outer to inner
    b = e + 1;
  }
  for (int dir : {+1, -1}) {
    const int tip = tips[dir > 0 ? 0 : 1];
    if (tip < 0) continue;
    // Toe (start_profile): where the material stood higher than level[tip] at the start.
    const double toe_x = (dir > 0 ? before.toe_hi : before.toe_lo)[static_cast<std::size_t>(tip)];
    if (!std::isfinite(toe_x)) continue;  // nothing stood that high inward of the tip
    // Front: the outermost edge of the points raising the tip column (a point reaching it
    // lies wholly in the connected deposit).
    const double front = dir > 0 ? after.hi[tip] : after.lo[tip];
    (dir > 0 ? r.x_max : r.x_min) = std::max(0.0, dir * (front - toe_x));
  }
  return r;
}

template <int D>
double StageTracker<D>::runout(const Particles<D>& P) const {
  const Runout r = runout_of(profile_, P, x0_, width_, threshold_, 0, floor_, procs_);
  return std::max(r.x_min, r.x_max);
}

template <int D>
StageMeasures StageTracker<D>::finish(const Particles<D>& P, double time, long steps, double kinetic_energy,
                                      double gravity_work, double strain_energy, double plastic_dissipation,
                                      const std::string& ended_by) const {
  StageMeasures m = m_;
  const MaterialExtent e = material_extent(P, procs_);
  m.end_time = time;
  m.steps = steps;
  m.ended_by = ended_by;
  const Runout r = runout_of(profile_, P, x0_, width_, threshold_, 0, floor_, procs_);
  m.runout_x_min = r.x_min;
  m.runout_x_max = r.x_max;
  m.runout = std::max(r.x_min, r.x_max);
  if constexpr (D == 3) {
    const Runout z = runout_of(profile_z_, P, z0_, width_, threshold_, 2, floor_, procs_);
    m.runout_z_min = z.x_min;
    m.runout_z_max = z.x_max;
  }
  m.max_displacement = max_displacement(P, procs_);
  m.height_end = e.y_max - e.y_min;
  m.gravity_work = gravity_work;
  m.kinetic_energy_change = kinetic_energy - kinetic_start_;
  m.strain_energy = strain_energy;
  m.plastic_dissipation = plastic_dissipation;
  for (std::size_t p = 0; p < P.size(); ++p)
    if (P.state[p].plastic_shear_strain > P.plastic_ref[p]) {
      m.plastic_volume += P.volume(p);
      ++m.plastic_points;
    }
  procs_.sum(&m.plastic_volume, 1);
  m.plastic_points = procs_.sum_of(m.plastic_points);
  const double threshold = rest_speed_ > 0.0 ? rest_speed_ : 0.01 * m.peak_mean_speed;
  if (!samples_.empty() && samples_.back().second < threshold && m.peak_mean_speed > 0.0) {
    double since = samples_.back().first;
    for (auto it = samples_.rbegin(); it != samples_.rend() && it->second < threshold; ++it)
      since = it->first;
    m.stop_time = since - m.start_time;
  }
  return m;
}

template MaterialExtent material_extent<2>(const Particles<2>&, const Processes&);
template MaterialExtent material_extent<3>(const Particles<3>&, const Processes&);
template SurfaceProfile surface_profile<2>(const Particles<2>&, double, double, int, int,
                                           const std::vector<double>&, const Processes&);
template SurfaceProfile surface_profile<3>(const Particles<3>&, double, double, int, int,
                                           const std::vector<double>&, const Processes&);
template SurfaceProfile start_profile<2>(const Particles<2>&, double, double, int, double, int, double,
                                         const Processes&);
template SurfaceProfile start_profile<3>(const Particles<3>&, double, double, int, double, int, double,
                                         const Processes&);
template Runout runout_of<2>(const SurfaceProfile&, const Particles<2>&, double, double, double, int, double,
                             const Processes&);
template Runout runout_of<3>(const SurfaceProfile&, const Particles<3>&, double, double, double, int, double,
                             const Processes&);
template class StageTracker<2>;
template class StageTracker<3>;

}  // namespace skred
