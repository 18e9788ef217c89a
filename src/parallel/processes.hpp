// The processes a run is distributed over (issue 55): MPI's world when skred was started by an
// MPI launcher (`mpirun -np N`), else the one process alone. The explicit solver's points are
// split among them in blocks of the grid (point_shares.hpp); each works on the box of nodes its
// points reach, and every grid sum the points make (mass, momentum, forces, remapped momentum, the
// filters' fields) is completed where the boxes overlap, after the per-thread scatter buffers
// (Transfer::reduce, transfer/box_exchange.hpp), so every process has the same bits at a node it
// holds. The implicit integrator sums its grid whole (process_sums.hpp). The points' own sums
// (energies, totals, the first failing point) are summed here too.
// mpi.h stays in processes.cpp: a single process never calls MPI.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace skred {

class Processes {
 public:
  Processes() = default;  // one process alone
  // MPI's world (start_processes must have run); one process alone if it has size 1. Not a
  // collective call.
  static Processes world();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool distributed() const { return size_ > 1; }
  // This process among those on its machine (that share its memory), and their number.
  int local_rank() const { return local_rank_; }
  int local_size() const { return local_size_; }

  // Collective (every process calls them in the same order; no-ops for one process):
  void sum(double* data, std::size_t n) const;  // in place
  void sum(long* data, std::size_t n) const;
  void min(double* data, std::size_t n) const;
  void min(long* data, std::size_t n) const;
  void max(double* data, std::size_t n) const;
  void bit_or(std::uint64_t* data, std::size_t n) const;  // in place: the union of bit sets
  long min(long v) const;
  long max(long v) const;
  bool any(bool v) const { return max(v ? 1L : 0L) > 0; }
  void barrier() const;
  long sum_of(long v) const {
    sum(&v, 1);
    return v;
  }
  // The sum of `v` over the processes of lower rank (the first global index of this one's points).
  long offset(long v) const;
  // Concatenates each process's `n` doubles in rank order into `all` (size: the sum of the n's),
  // on every process.
  void gather(const double* data, std::size_t n, double* all, std::size_t all_n) const;
  // Sends `per` longs to each process q (send[q per], ...) and receives as many from each into
  // recv, in rank order (MPI_Alltoall).
  void all_to_all(const long* send, int per, long* recv) const;

 private:
  int rank_ = 0, size_ = 1, local_rank_ = 0, local_size_ = 1;
  void* comm_ = nullptr;  // the MPI communicator (MPI_Comm), when distributed
};

// What this process has exchanged with the others so far: its calls that communicate, the
// messages it sent to single processes in them (a star forest's or an all-to-all's to each
// neighbour; an allreduce counts none), and the bytes it gave (an allreduce of n doubles: 8 n; a
// gather: its own part). For the exchange's share of a step (skred bench; docs/studies).
struct Exchanged {
  long calls = 0, messages = 0;
  long forests = 0;  // star forests set up (star_forest.hpp): each costs a few collective calls
  double bytes = 0.0;
};
Exchanged exchanged();
// Adds to exchanged() (the exchanges that other classes make: star_forest.hpp).
void count_exchange(long calls, long messages, double bytes, long forests = 0);

// Whether this build has MPI and PETSc (CMake's SKRED_MPI, on by default). Without them
// (processes_alone.cpp) skred runs in one process and has no implicit integrator, whose solves
// are PETSc's; main() and the scenario parser say so when asked for either.
bool built_with_mpi();

// MPI_Init when started by an MPI launcher (launched_processes() > 1); call once, first thing.
// Returns the world's size.
int start_processes(int* argc, char*** argv);
// MPI_Finalize if started, after the libraries that work on MPI (PETSc) stopped: their `stop`
// functions (registered with stop_before_finish) run first, last registered first. The exit code
// passes through.
int finish_processes(int code);
void stop_before_finish(void (*stop)());
// Stops every process of the world with `code`, after this one printed its error (one process
// that fails while the others wait in a collective call would leave them waiting for ever).
[[noreturn]] void abort_processes(int code);

}  // namespace skred
