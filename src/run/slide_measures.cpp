#include "run/slide_measures.hpp"

#include <algorithm>
#include <cmath>

namespace skred {

MaterialExtent material_extent(const Particles<2>& P) {
  double x_min = INFINITY, x_max = -INFINITY, y_min = INFINITY, y_max = -INFINITY;
  const long n = static_cast<long>(P.size());
#pragma omp parallel for reduction(min : x_min, y_min) reduction(max : x_max, y_max)
  for (long p = 0; p < n; ++p) {
    // Corners x_p + F (+-l0x, +-l0y); the extreme corner along each axis.
    const Vec<2> r = P.F[p].cwiseAbs() * P.half0[p];
    x_min = std::min(x_min, P.x[p][0] - r[0]);
    x_max = std::max(x_max, P.x[p][0] + r[0]);
    y_min = std::min(y_min, P.x[p][1] - r[1]);
    y_max = std::max(y_max, P.x[p][1] + r[1]);
  }
  const MaterialExtent e{x_min, x_max, y_min, y_max};
  return e;
}

StageTracker::StageTracker(std::string name, const Particles<2>& P, double time,
                           double kinetic_energy, double rest_speed, double rest_time)
    : start_(material_extent(P)), kinetic_start_(kinetic_energy), rest_speed_(rest_speed),
      rest_time_(rest_time) {
  m_.name = std::move(name);
  m_.start_time = time;
  m_.height_start = start_.y_max - start_.y_min;
  plastic_start_.resize(P.size());
  for (std::size_t p = 0; p < P.size(); ++p) plastic_start_[p] = P.state[p].plastic_shear_strain;
}

bool StageTracker::observe(double time, double mean_speed) {
  if (mean_speed > m_.peak_mean_speed) {
    m_.peak_mean_speed = mean_speed;
    m_.peak_time = time - m_.start_time;
  }
  m_.final_mean_speed = mean_speed;
  samples_.emplace_back(time, mean_speed);
  if (rest_speed_ <= 0.0) return false;
  if (mean_speed >= rest_speed_) {
    quiet_since_.reset();
    return false;
  }
  if (!quiet_since_) quiet_since_ = time;
  return time - *quiet_since_ >= rest_time_ * (1.0 - 1e-9);
}

double StageTracker::runout(const Particles<2>& P) const {
  const MaterialExtent e = material_extent(P);
  return std::max(start_.x_min - e.x_min, e.x_max - start_.x_max);
}

StageMeasures StageTracker::finish(const Particles<2>& P, double time, long steps,
                                   double kinetic_energy, double gravity_work,
                                   double strain_energy, double plastic_dissipation,
                                   const std::string& ended_by) const {
  StageMeasures m = m_;
  const MaterialExtent e = material_extent(P);
  m.end_time = time;
  m.steps = steps;
  m.ended_by = ended_by;
  m.runout_x_min = start_.x_min - e.x_min;
  m.runout_x_max = e.x_max - start_.x_max;
  m.runout = std::max(m.runout_x_min, m.runout_x_max);
  m.height_end = e.y_max - e.y_min;
  m.gravity_work = gravity_work;
  m.kinetic_energy_change = kinetic_energy - kinetic_start_;
  m.strain_energy = strain_energy;
  m.plastic_dissipation = plastic_dissipation;
  for (std::size_t p = 0; p < P.size(); ++p)
    if (P.state[p].plastic_shear_strain > plastic_start_[p]) {
      m.plastic_volume += P.volume(p);
      ++m.plastic_points;
    }
  const double threshold = rest_speed_ > 0.0 ? rest_speed_ : 0.01 * m.peak_mean_speed;
  if (!samples_.empty() && samples_.back().second < threshold && m.peak_mean_speed > 0.0) {
    double since = samples_.back().first;
    for (auto it = samples_.rbegin(); it != samples_.rend() && it->second < threshold; ++it)
      since = it->first;
    m.stop_time = since - m.start_time;
  }
  return m;
}

}  // namespace skred
