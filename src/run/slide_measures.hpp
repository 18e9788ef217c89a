// What an engineer reads off a finished stage of a slide (issue: slide measures): runout,
// deposit height, mean speeds (Thesis eq. 5.12), work of gravity (eq. 5.13), the energy
// balance, the plastified volume and the time the slide stopped.
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/particles.hpp"
#include "io/summary_writer.hpp"

namespace skred {

// Extent of the material: the deformed voxels' corners x_p + F_p (+-l0) (Thesis eq. 3.6-3.12).
struct MaterialExtent {
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0;
};
MaterialExtent material_extent(const Particles<2>& P);

// Top of the material in columns of `width` from x0 (the highest deformed-voxel corner in
// each column; -inf where there is none).
std::vector<double> surface_profile(const Particles<2>& P, double x0, double width, int bins);

// Runout from the surface profiles before and after, towards +x and -x: the tip is the
// outermost column the deposit has raised by more than `threshold`; the toe is the outermost
// column inward of the tip whose original surface stood higher than the original surface at
// the tip (for a slope: the original toe; for a column: its edge). Runout = |tip - toe|.
struct Runout {
  double x_min = 0.0, x_max = 0.0;
};
Runout runout_of(const std::vector<double>& before, const std::vector<double>& after,
                 double width, double threshold);

// Follows one stage: record the start, observe the mean speed as the run goes, finish.
class StageTracker {
 public:
  // The surface profile is taken in columns of `width` (a grid cell) over [x0, x0 + length].
  StageTracker(std::string name, const Particles<2>& P, double time, double kinetic_energy,
               double rest_speed, double rest_time, double x0, double width, double length);
  // Records a sample of the mean speed at `time`; true once the rest criterion is met.
  bool observe(double time, double mean_speed);
  StageMeasures finish(const Particles<2>& P, double time, long steps, double kinetic_energy,
                       double gravity_work, double strain_energy, double plastic_dissipation,
                       const std::string& ended_by) const;
  // Current runout and deposit height, for the series rows.
  double runout(const Particles<2>& P) const;

 private:
  StageMeasures m_;
  MaterialExtent start_;
  std::vector<double> plastic_start_;  // plastic shear strain per point at the stage start
  double kinetic_start_ = 0.0;
  double rest_speed_ = 0.0, rest_time_ = 0.0, threshold_ = 0.0;
  double x0_ = 0.0, width_ = 1.0, length_ = 0.0;
  std::vector<double> profile_;  // surface profile at the stage start
  int bins() const { return std::max(1, static_cast<int>(std::lround(length_ / width_))); }
  std::optional<double> quiet_since_;  // time the mean speed last fell below rest_speed
  std::vector<std::pair<double, double>> samples_;  // (time, mean speed)
};

}  // namespace skred
