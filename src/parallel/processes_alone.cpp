// The processes of a build without MPI (CMake's SKRED_MPI=OFF; processes.hpp): one process
// alone, whose collective calls leave their data as they are. main() refuses a start by an MPI
// launcher before any of these is called (built_with_mpi).
#include <algorithm>
#include <cstdlib>
#include <vector>

#include "parallel/processes.hpp"

namespace skred {

namespace {
std::vector<void (*)()> stops;  // stop_before_finish
}  // namespace

bool built_with_mpi() { return false; }

int start_processes(int*, char***) { return 1; }

void stop_before_finish(void (*stop)()) { stops.push_back(stop); }

int finish_processes(int code) {
  for (auto it = stops.rbegin(); it != stops.rend(); ++it) (*it)();
  stops.clear();
  return code;
}

void abort_processes(int code) { std::exit(code); }

Processes Processes::world() { return Processes{}; }

void Processes::sum(double*, std::size_t) const {}
void Processes::sum(long*, std::size_t) const {}
void Processes::min(double*, std::size_t) const {}
void Processes::min(long*, std::size_t) const {}
void Processes::max(double*, std::size_t) const {}
void Processes::bit_or(std::uint64_t*, std::size_t) const {}
long Processes::min(long v) const { return v; }
long Processes::max(long v) const { return v; }
void Processes::barrier() const {}
long Processes::offset(long) const { return 0; }

void Processes::gather(const double* data, std::size_t n, double* all, std::size_t all_n) const {
  std::copy_n(data, std::min(n, all_n), all);
}

void Processes::all_to_all(const long* send, int per, long* recv) const { std::copy_n(send, per, recv); }

}  // namespace skred
