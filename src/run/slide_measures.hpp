// What an engineer reads off a finished stage of a slide (issue: slide measures): runout,
// deposit height, mean speeds (Thesis eq. 5.12), work of gravity (eq. 5.13), the energy
// balance, the plastified volume and the time the slide stopped.
#pragma once
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/particles.hpp"
#include "io/summary_writer.hpp"
#include "parallel/processes.hpp"

namespace skred {

// Extent of the material: the points x_p +- their current half-size l0 det(F_p)^(1/d) (the
// GIMP domain, Thesis eq. 3.23). In 2D z_min = z_max = 0. Every function here that reads the
// points takes the processes they are split among (parallel/processes.hpp) and answers for all
// of them, on every process (collective).
struct MaterialExtent {
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0, z_min = 0.0, z_max = 0.0;
};
template <int D>
MaterialExtent material_extent(const Particles<D>& P, const Processes& procs = {});

// Surface profile in columns of `width` from x0 along `axis` (0: x; 2: z, in 3D), each point
// counted as its domain x_p +- l_p, l_p = l0 det(F_p)^(1/d) (the GIMP domain): per column, `top`
// is the highest x_p[1] + l_p over the points that reach it (-inf where there is none), and
// `lo`, `hi` the outermost material edges along the axis, min (x_p - l_p) and max (x_p + l_p),
// over those of them whose top stands higher than above[column] (all of them if `above` is
// empty; +inf and -inf where there is none). In 3D a column is a slice across the whole
// domain (for axis 0, every z; for axis 2, every x).
// `toe_hi`, `toe_lo` (start_profile): per column t taken as the deposit's tip towards +x, -x, the
// toe (runout_of), or -inf, +inf where there is none.
struct SurfaceProfile {
  std::vector<double> top, lo, hi;
  std::vector<double> toe_hi, toe_lo;
};
template <int D>
SurfaceProfile surface_profile(const Particles<D>& P, double x0, double width, int bins, int axis = 0,
                               const std::vector<double>& above = {}, const Processes& procs = {});

// The profile at a stage's start that runout_of measures from: surface_profile, and for each
// column t as the tip the toe, found from the points then. The toe column is the outermost
// column inward of t whose surface stood higher than level(t) = the surface at t (`floor` where
// t held no material) plus `threshold`; the toe is the outermost edge x_p + l_p (towards -x:
// x_p - l_p) of the points that reach the toe column and stand higher than level(t): where the
// material stood that high, by the rule that finds the front now. (Until 2026-11-30 a slope's
// toe was where its column tops, joined between column centres, came down to level(t): a
// column's top is its highest point's, which on a face lies at the column's uphill side, so
// that toe lay 0.5-0.8 of a cell beyond the material's edge; docs/method.md, "The runout
// measure".)
template <int D>
SurfaceProfile start_profile(const Particles<D>& P, double x0, double width, int bins, double threshold,
                             int axis = 0, double floor = -INFINITY, const Processes& procs = {});

// Runout towards +x and -x (or z) from the profile `before` (start_profile, with the same
// `threshold` and `floor`) and the points now. The connected deposit lies in the run of
// non-empty columns around the highest one; per side, it is the widest run of columns raised by
// more than `threshold` that reaches that side of the highest (of equal ones the outer: over a
// base layer, where every column holds material, a clump resting beyond a column the slide left
// unraised is not the deposit); its tip the outer end of that run. The runout is continuous, not
// counted in columns: front - toe, where the front is the outermost edge x_p +- l_p of the
// points that raise the tip column, i.e. stand higher than level(tip), and the toe
// (start_profile) the outermost edge of the points that stood that high at the start, in the
// toe column: the distance the material's edge at that level moved. Never negative. A column
// that held no material has no original surface: any material raises it, unless `floor` is
// finite, which then stands for its surface.
struct Runout {
  double x_min = 0.0, x_max = 0.0;
};
template <int D>
Runout runout_of(const SurfaceProfile& before, const Particles<D>& P, double x0, double width,
                 double threshold, int axis = 0, double floor = -INFINITY, const Processes& procs = {});

// Reads or writes a stage's measures through `a` (see StageTracker::archive).
template <class A>
void archive_measures(A& a, StageMeasures& m) {
  a(m.name);
  a(m.start_time);
  a(m.end_time);
  a(m.steps);
  a(m.ended_by);
  a(m.runout_x_min);
  a(m.runout_x_max);
  a(m.runout);
  a(m.max_displacement);
  a(m.height_start);
  a(m.height_end);
  a(m.peak_mean_speed);
  a(m.peak_time);
  a(m.final_mean_speed);
  a(m.gravity_work);
  a(m.kinetic_energy_change);
  a(m.strain_energy);
  a(m.plastic_dissipation);
  a(m.plastic_volume);
  a(m.plastic_points);
  a(m.stop_time);
  a(m.rest_measure);
  a(m.dilated_points);
  a(m.dilated_first_time);
  a(m.dilated_last_time);
}

// Follows one stage: record the start, observe the mean speed as the run goes, finish.
// In 3D the runout is measured along x as in 2D (`runout`, `runout_x_min/max`), and along z
// the same way from profiles across z (`runout_z_min/max`).
template <int D>
class StageTracker {
 public:
  // The surface profile is taken in columns of `width` (a grid cell) over [x0, x0 + length]
  // (3D: also over [z0, z0 + z_length] along z). `thickness` is the stage's runout_thickness:
  // 0 takes the runout at half a cell with any material raising a column that held none at the
  // stage start; > 0 takes it at that thickness, with the floor (the lowest material edge then)
  // for such a column's original surface (runout_of's threshold and floor). Records every
  // point's plastic shear strain in P.plastic_ref (a particle field, so it follows the points
  // through every change of their number or order). Its measures are over the points of all of
  // `procs` (set again by set_processes after a restart: they are not archived).
  StageTracker() = default;  // to be filled by archive() (checkpoint restart)
  StageTracker(std::string name, Particles<D>& P, double time, double kinetic_energy, double rest_speed,
               double rest_time, double x0, double width, double length, double thickness = 0.0,
               double z0 = 0.0, double z_length = 0.0, const Processes& procs = {});
  void set_processes(const Processes& procs) { procs_ = procs; }
  // Records a sample of the mean speed at `time` (eq. 5.12: peak and final speed) and of the
  // speed the rest test reads (`rest_measure_speed`: the same, or the material's, as
  // Stage::rest_measure says; also the stop time's); true once the rest criterion is met.
  bool observe(double time, double mean_speed, double rest_measure_speed);
  // The rest test on displacement (Stage::rest_measure "displacement"): a window starts at
  // `time` (P.x_rest = P.x). observe_window, at every series row, records the mean speed
  // (eq. 5.12) as observe does; once the window has lasted rest_time it takes the window's mean
  // speed of the material, sum_p m_p |x_p - x_rest_p| / (sum_p m_p (time - start)), as a sample
  // at the window's start and starts the next window. True once that speed is below rest_speed.
  void start_window(Particles<D>& P, double time);
  bool observe_window(Particles<D>& P, double time, double mean_speed);
  StageMeasures finish(const Particles<D>& P, double time, long steps, double kinetic_energy,
                       double gravity_work, double strain_energy, double plastic_dissipation,
                       const std::string& ended_by) const;
  // Records `moved` points that joined a dilated continuum at `time` (Paper III §C.3.2).
  void dilated(long moved, double time) {
    if (moved <= 0) return;
    m_.dilated_points += moved;
    if (!m_.dilated_first_time) m_.dilated_first_time = time - m_.start_time;
    m_.dilated_last_time = time - m_.start_time;
  }
  // Current runout and deposit height, for the series rows.
  double runout(const Particles<D>& P) const;
  double kinetic_start() const { return kinetic_start_; }  // kinetic energy at the stage start
  double height_start() const { return m_.height_start; }  // the material's height then
  // The largest displacement of a point in the stage, max_p |x_p - x_ref_p|.
  static double max_displacement(const Particles<D>& P, const Processes& procs = {});
  double max_displacement_of(const Particles<D>& P) const { return max_displacement(P, procs_); }

  // Reads or writes the tracker's whole state through `a` (see run/checkpointing.cpp):
  // a(value) for every member.
  template <class A>
  void archive(A& a) {
    archive_measures(a, m_);
    a(start_.x_min);
    a(start_.x_max);
    a(start_.y_min);
    a(start_.y_max);
    a(kinetic_start_);
    a(rest_speed_);
    a(rest_time_);
    a(threshold_);
    a(floor_);
    a(x0_);
    a(width_);
    a(length_);
    a(z0_);
    a(z_length_);
    for (SurfaceProfile* s : {&profile_z_, &profile_}) {
      a(s->top);
      a(s->lo);
      a(s->hi);
      a(s->toe_hi);
      a(s->toe_lo);
    }
    a(quiet_since_);
    a(samples_);
    a(window_start_);
  }

 private:
  StageMeasures m_;
  Processes procs_;
  MaterialExtent start_;
  double kinetic_start_ = 0.0;
  double rest_speed_ = 0.0, rest_time_ = 0.0, threshold_ = 0.0;
  double floor_ = -INFINITY;  // original surface of the columns that held no material
  double x0_ = 0.0, width_ = 1.0, length_ = 0.0, z0_ = 0.0, z_length_ = 0.0;
  SurfaceProfile profile_;    // surface profile along x at the stage start
  SurfaceProfile profile_z_;  // 3D: along z
  int bins() const { return std::max(1, static_cast<int>(std::lround(length_ / width_))); }
  int bins_z() const { return std::max(1, static_cast<int>(std::lround(z_length_ / width_))); }
  std::optional<double> quiet_since_;               // time the mean speed last fell below rest_speed
  std::vector<std::pair<double, double>> samples_;  // (time, mean speed)
  double window_start_ = NAN;                       // the displacement window's start (NaN: none)
  void record_speed(double time, double mean_speed);
};

}  // namespace skred
