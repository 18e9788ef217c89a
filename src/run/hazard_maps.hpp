// Hazard maps of a 3D run (docs/scenario.md, "Hazard maps (3D)"): per column of the background
// grid's x-z footprint, the deposit thickness, the change of the material's top, the largest
// speed and displacement reached and the time the flow arrived. The running maxima and the
// arrival are taken in one pass over the points at every series row (not every step).
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "parallel/processes.hpp"

namespace skred {

// One set of maps, row-major over the columns: index i + nx * j for the x cell i, z cell j.
struct MapSet {
  std::vector<double> top_start;         // the material's top at the start [m] (the floor where none)
  std::vector<double> max_speed;         // largest |v_p| of a point in the column [m/s]
  std::vector<double> max_displacement;  // largest |x_p - x_ref_p| of a point in the column [m]
  std::vector<double> arrival;           // first time a moved point was in the column [s]; NaN: never
  std::vector<double> thickness;         // initial volume of the moved points in the column / its area [m]
  std::vector<double> height_change;     // the top at the end less top_start [m]
  double floor = 0.0;                    // the lowest material edge at the start (empty columns' top)
  template <class A>
  void archive(A& a) {
    for (std::vector<double>* v :
         {&top_start, &max_speed, &max_displacement, &arrival, &thickness, &height_change})
      a(*v);
    a(floor);
  }
};

// The maps' names, in file order: deposit_thickness, height_change, max_speed,
// max_displacement, arrival_time, terrain (top_start: the hillshade of `skred render --map`).
const std::vector<std::string>& map_names();

class HazardMaps {
 public:
  HazardMaps() = default;  // off
  // Columns of side `h` from (x0, z0), nx x nz of them; a point has moved once it is more than
  // `threshold` from where it was at its stage's start.
  HazardMaps(double x0, double z0, double h, int nx, int nz, double threshold);
  bool enabled() const { return nx_ > 0; }
  // The processes the points are split among: the maps are over all of their points, and the
  // calls below collective (not archived: set again after a restart).
  void set_processes(const Processes& procs) { procs_ = procs; }
  const Processes& processes() const { return procs_; }
  int nx() const { return nx_; }
  int nz() const { return nz_; }
  double cell() const { return h_; }

  // The run's start (its top and floor), a stage's start at `time`, a sample at `time` (the
  // running maxima and the arrival), a stage's end (its thickness and change of top; merged
  // into the run's maps: maxima, earliest arrival in run time, the change of top from the run
  // start, and the thickness of the points that moved in any stage so far, which finish_stage
  // marks in P.moved).
  void begin_run(const Particles<3>& P);
  void begin_stage(const Particles<3>& P, double time);
  void sample(const Particles<3>& P, double time);
  void finish_stage(Particles<3>& P);

  const MapSet& run() const { return run_; }
  const MapSet& stage() const { return stage_; }
  // The value of map `name` (map_names()) of `set`, row-major.
  static const std::vector<double>& field(const MapSet& set, const std::string& name);

  template <class A>
  void archive(A& a) {
    a(x0_), a(z0_), a(h_), a(nx_), a(nz_), a(threshold_), a(stage_start_);
    run_.archive(a);
    stage_.archive(a);
  }

 private:
  double x0_ = 0.0, z0_ = 0.0, h_ = 1.0;
  int nx_ = 0, nz_ = 0;
  double threshold_ = 0.0, stage_start_ = 0.0;
  MapSet run_, stage_;
  Processes procs_;
  long column_of(const Vec<3>& x) const;  // -1 outside the footprint
  double tops(const Particles<3>& P, std::vector<double>& top) const;
  void start(const Particles<3>& P, MapSet& set) const;
};

}  // namespace skred
