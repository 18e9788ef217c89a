// Hazard maps of a 3D run (hazard_maps.hpp; docs/scenario.md, "Hazard maps (3D)").
#include "run/hazard_maps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace skred {

const std::vector<std::string>& map_names() {
  static const std::vector<std::string> names = {"deposit_thickness", "height_change", "max_speed",
                                                 "max_displacement",  "arrival_time",  "terrain"};
  return names;
}

HazardMaps::HazardMaps(double x0, double z0, double h, int nx, int nz, double threshold)
    : x0_(x0), z0_(z0), h_(h), nx_(nx), nz_(nz), threshold_(threshold) {}

long HazardMaps::column_of(const Vec<3>& x) const {
  const double u = std::floor((x[0] - x0_) / h_), w = std::floor((x[2] - z0_) / h_);
  if (!(u >= 0 && u < nx_ && w >= 0 && w < nz_)) return -1;
  return static_cast<long>(u) + static_cast<long>(nx_) * static_cast<long>(w);
}

// The top of each column: the highest edge x_p[1] + l_p of its points, l_p = l0 det(F_p)^(1/3)
// (the GIMP domain, Thesis eq. 3.23); -inf where it holds none. Returns the lowest edge of all.
double HazardMaps::tops(const Particles<3>& P, std::vector<double>& top) const {
  double floor = std::numeric_limits<double>::infinity();
  top.assign(static_cast<std::size_t>(nx_) * nz_, -std::numeric_limits<double>::infinity());
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double l = P.half0[p][1] * std::cbrt(P.F[p].determinant());
    floor = std::min(floor, P.x[p][1] - l);
    if (const long c = column_of(P.x[p]); c >= 0) top[c] = std::max(top[c], P.x[p][1] + l);
  }
  procs_.max(top.data(), top.size());
  procs_.min(&floor, 1);
  return floor;
}

// A new set: the tops now (the floor where a column holds no material), no maxima, no arrival.
void HazardMaps::start(const Particles<3>& P, MapSet& set) const {
  set = {};
  set.floor = tops(P, set.top_start);
  for (double& t : set.top_start)
    if (std::isinf(t)) t = set.floor;
  const std::size_t n = set.top_start.size();
  set.max_speed.assign(n, 0.0);
  set.max_displacement.assign(n, 0.0);
  set.arrival.assign(n, NAN);
  set.thickness.assign(n, 0.0);
  set.height_change.assign(n, 0.0);
}

void HazardMaps::begin_run(const Particles<3>& P) {
  if (enabled()) start(P, run_);
}

void HazardMaps::begin_stage(const Particles<3>& P, double time) {
  if (!enabled()) return;
  stage_start_ = time;
  start(P, stage_);
}

// One pass over the points, no allocation: the maxima where the points are now, and the arrival
// (stage time) of the first point that has moved more than the threshold.
void HazardMaps::sample(const Particles<3>& P, double time) {
  if (!enabled()) return;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const long c = column_of(P.x[p]);
    if (c < 0) continue;
    const double d = (P.x[p] - P.x_ref[p]).norm();
    stage_.max_speed[c] = std::max(stage_.max_speed[c], P.v[p].norm());
    stage_.max_displacement[c] = std::max(stage_.max_displacement[c], d);
    if (d > threshold_ && std::isnan(stage_.arrival[c])) stage_.arrival[c] = time - stage_start_;
  }
  if (!procs_.distributed()) return;
  procs_.max(stage_.max_speed.data(), stage_.max_speed.size());
  procs_.max(stage_.max_displacement.data(), stage_.max_displacement.size());
  // Every process samples at the same times: a column's arrival is this sample's time wherever
  // one of them found it, so the earliest (NaN: none yet, as +inf) is every process's.
  for (double& a : stage_.arrival)
    if (std::isnan(a)) a = INFINITY;
  procs_.min(stage_.arrival.data(), stage_.arrival.size());
  for (double& a : stage_.arrival)
    if (std::isinf(a)) a = NAN;
}

void HazardMaps::finish_stage(Particles<3>& P) {
  if (!enabled()) return;
  const double area = h_ * h_;
  std::fill(stage_.thickness.begin(), stage_.thickness.end(), 0.0);
  std::fill(run_.thickness.begin(), run_.thickness.end(), 0.0);
  if (P.moved.size() != P.size()) P.moved.assign(P.size(), 0);  // the first stage's end
  for (std::size_t p = 0; p < P.size(); ++p) {
    const bool moved = (P.x[p] - P.x_ref[p]).norm() > threshold_;
    P.moved[p] |= static_cast<std::uint8_t>(moved);
    if (const long c = column_of(P.x[p]); c >= 0) {  // volumes: mass over the density at the start
      if (moved) stage_.thickness[c] += P.volume0[p] / area;
      if (P.moved[p]) run_.thickness[c] += P.volume0[p] / area;
    }
  }
  procs_.sum(stage_.thickness.data(), stage_.thickness.size());
  procs_.sum(run_.thickness.data(), run_.thickness.size());
  std::vector<double> top;
  tops(P, top);
  for (std::size_t c = 0; c < top.size(); ++c) {
    // A column empty now stands at the floor of the start (no change if it was empty then).
    const bool empty = std::isinf(top[c]);
    stage_.height_change[c] = (empty ? stage_.floor : top[c]) - stage_.top_start[c];
    run_.height_change[c] = (empty ? run_.floor : top[c]) - run_.top_start[c];
    run_.max_speed[c] = std::max(run_.max_speed[c], stage_.max_speed[c]);
    run_.max_displacement[c] = std::max(run_.max_displacement[c], stage_.max_displacement[c]);
    if (std::isnan(run_.arrival[c])) run_.arrival[c] = stage_.arrival[c] + stage_start_;
  }
}

const std::vector<double>& HazardMaps::field(const MapSet& set, const std::string& name) {
  if (name == "deposit_thickness") return set.thickness;
  if (name == "height_change") return set.height_change;
  if (name == "max_speed") return set.max_speed;
  if (name == "max_displacement") return set.max_displacement;
  if (name == "arrival_time") return set.arrival;
  if (name == "terrain") return set.top_start;
  throw std::logic_error("no hazard map named " + name);
}

}  // namespace skred
