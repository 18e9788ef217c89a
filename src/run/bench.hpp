// The built-in throughput benchmarks. Reports particle-updates per second.
//  - "block": an elastic soil block settling under gravity in a box (fixed base, roller
//    walls, 2 x 2 points per cell), of adjustable size;
//  - "column": the Mohr-Coulomb column collapse the peer figures were measured on: domain
//    10 m x 4.5 m, cell 0.05 m / refine, column 2 m x 4 m against the left wall, 2 x 2 points
//    per cell (12,800 points at refine 1), phi = 30, psi = 0, c = 0.5 kPa, E = 10 MPa,
//    nu = 0.3, rho = 1800, K0 = nu/(1 - nu), roller sides, fixed base, USF, dt = 0.1 ms.
//    With dim = 3 the same column as a slab 4 cells thick between roller z walls, 2 x 2 x 2
//    points per cell (102,400 points at refine 1). With bodies = 2 the column is two bodies,
//    its lower and upper half (y < 2 m, y > 2 m), in frictional contact with mu = tan(phi)
//    (Paper III §C.2.7): the cost of contact.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "core/particles.hpp"
#include "parallel/processes.hpp"
#include "scenario/scenario.hpp"

namespace skred {

struct BenchOptions {
  std::string problem = "block";  // "block" or "column"
  int refine = 1;                 // column: cells per 0.05 m (particles grow as refine^2)
  int dim = 2;                    // column: 3 for the 3D slab
  long particles = 200000;        // approximate number of material points
  int steps = 100;
  int repeats = 5;
  int threads = 1;
  Interpolation interpolation = Interpolation::Gimp;
  int quadrature_points = 2;
  StressScheme scheme = StressScheme::Averaged;
  VelocityTransfer velocity_transfer = VelocityTransfer::Flip;
  double xpic_period = 0.0;  // xpic: filter once per this many crossing times h/c (0: every step)
  // The cell-averaged volumetric strain; off (each point's own), as the benches were measured,
  // whatever a scenario's "auto" would pick.
  bool volumetric_averaging = false;
  long sort_every = kSortEvery;            // sort the points by cell every N steps, as a run does; 0: never
  int bodies = 1;                          // column: 2 for two halves in frictional contact
  std::string contact_detection = "fill";  // with bodies = 2: the [[contact]] detection rule
  // The processes the points are split among (under mpirun; parallel/processes.hpp): each steps
  // its share, and the figures are every process's together.
  Processes processes;
};

struct BenchResult {
  long particles = 0;      // over every process
  long own_particles = 0;  // this process's share
  long nodes = 0;
  std::vector<double> updates_per_second;  // one per repeat
  double median = 0.0;
  double peak_rss_bytes = 0.0;
  double idle_rss_bytes = 0.0;  // resident before the bench built anything
  double runout = 0.0;          // column: front advance after the timed steps [m]
  long yielding = 0;            // column: points whose last stress update was plastic
  // Distributed: the calls that communicate, the messages to single processes in them and the
  // bytes a process gave, per timed step (parallel/processes.hpp, exchanged()): the processes'
  // mean, and the most.
  double calls_per_step = 0.0, bytes_per_step = 0.0;  // (bytes: the processes' mean)
  double messages_per_step = 0.0;                     // (the processes' mean)
  double forests_per_step = 0.0;                      // star forests set up
  double most_bytes_per_step = 0.0;                   // the most a process sent
  std::string status = "completed";
  // Seconds per phase of the time step over the timed steps of all repeats (in step order).
  std::vector<std::pair<std::string, double>> phase_seconds;
};

BenchResult run_bench(const BenchOptions& opt);

}  // namespace skred
