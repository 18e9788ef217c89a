// The built-in throughput benchmark: an elastic soil block settling under gravity in a box
// (fixed base, roller walls, 2 x 2 points per cell). Reports particle-updates per second.
#pragma once
#include <string>
#include <vector>

#include "scenario/scenario.hpp"

namespace skred {

struct BenchOptions {
  long particles = 200000;  // approximate number of material points
  int steps = 100;
  int repeats = 5;
  int threads = 1;
  Interpolation interpolation = Interpolation::Gimp;
  int quadrature_points = 2;
  StressScheme scheme = StressScheme::Averaged;
};

struct BenchResult {
  long particles = 0;
  long nodes = 0;
  std::vector<double> updates_per_second;  // one per repeat
  double median = 0.0;
  double peak_rss_bytes = 0.0;
};

BenchResult run_bench(const BenchOptions& opt);

// Peak resident set size of this process in bytes (VmHWM), 0 if unknown.
double peak_rss_bytes();

}  // namespace skred
