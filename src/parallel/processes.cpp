// The processes of a distributed run over MPI (processes.hpp).
#include "parallel/processes.hpp"

// MPI's C interface only (OpenMPI's mpi.h otherwise pulls in its C++ bindings' library).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

namespace skred {

namespace {

bool started = false;
int machine_rank = 0, machine_size = 1;  // among the processes of this machine (start_processes)
std::vector<void (*)()> stops;           // stop_before_finish

MPI_Comm comm_of(void* c) { return c ? static_cast<MPI_Comm>(c) : MPI_COMM_SELF; }

}  // namespace

bool built_with_mpi() { return true; }

int start_processes(int* argc, char*** argv) {
  int provided = 0;
  // OpenMP threads compute between the calls; only the main thread calls MPI.
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  started = true;
  int size = 1, rank = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm machine;  // the processes that share this one's memory
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &machine);
  MPI_Comm_rank(machine, &machine_rank);
  MPI_Comm_size(machine, &machine_size);
  MPI_Comm_free(&machine);
  return size;
}

void stop_before_finish(void (*stop)()) { stops.push_back(stop); }

int finish_processes(int code) {
  for (auto it = stops.rbegin(); it != stops.rend(); ++it) (*it)();
  stops.clear();
  if (started) {
    started = false;
    MPI_Finalize();
  }
  return code;
}

void abort_processes(int code) {
  if (started) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

Processes Processes::world() {
  Processes p;
  if (!started) return p;
  MPI_Comm_rank(MPI_COMM_WORLD, &p.rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &p.size_);
  if (p.size_ > 1) p.comm_ = static_cast<void*>(MPI_COMM_WORLD);
  p.local_rank_ = machine_rank;
  p.local_size_ = machine_size;
  return p;
}

namespace {
// data <- op over the processes, in place.
void allreduce(void* comm, void* data, std::size_t n, MPI_Datatype type, MPI_Op op) {
  if (!comm || n == 0) return;
  int bytes = 0;
  MPI_Type_size(type, &bytes);
  count_exchange(1, 0, static_cast<double>(bytes) * static_cast<double>(n));
  MPI_Allreduce(MPI_IN_PLACE, data, static_cast<int>(n), type, op, comm_of(comm));
}
}  // namespace

void Processes::sum(double* data, std::size_t n) const { allreduce(comm_, data, n, MPI_DOUBLE, MPI_SUM); }
void Processes::sum(long* data, std::size_t n) const { allreduce(comm_, data, n, MPI_LONG, MPI_SUM); }
void Processes::min(double* data, std::size_t n) const { allreduce(comm_, data, n, MPI_DOUBLE, MPI_MIN); }
void Processes::min(long* data, std::size_t n) const { allreduce(comm_, data, n, MPI_LONG, MPI_MIN); }
void Processes::max(double* data, std::size_t n) const { allreduce(comm_, data, n, MPI_DOUBLE, MPI_MAX); }
void Processes::bit_or(std::uint64_t* data, std::size_t n) const {
  allreduce(comm_, data, n, MPI_UINT64_T, MPI_BOR);
}

long Processes::min(long v) const {
  allreduce(comm_, &v, 1, MPI_LONG, MPI_MIN);
  return v;
}

long Processes::max(long v) const {
  allreduce(comm_, &v, 1, MPI_LONG, MPI_MAX);
  return v;
}

void Processes::barrier() const {
  if (!distributed()) return;
  count_exchange(1, 0, 0.0);
  MPI_Barrier(comm_of(comm_));
}

long Processes::offset(long v) const {
  long below = 0;
  if (distributed()) {
    count_exchange(1, 0, sizeof v);
    MPI_Exscan(&v, &below, 1, MPI_LONG, MPI_SUM, comm_of(comm_));
    if (rank_ == 0) below = 0;  // (MPI_Exscan leaves rank 0's result undefined)
  }
  return below;
}

void Processes::gather(const double* data, std::size_t n, double* all, std::size_t all_n) const {
  if (!distributed()) {
    for (std::size_t i = 0; i < n && i < all_n; ++i) all[i] = data[i];
    return;
  }
  std::vector<int> counts(static_cast<std::size_t>(size_)), starts(static_cast<std::size_t>(size_));
  const int mine = static_cast<int>(n);
  count_exchange(2, 0, sizeof mine + static_cast<double>(n) * sizeof(double));
  MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_of(comm_));
  int at = 0;
  for (int r = 0; r < size_; ++r) {
    starts[static_cast<std::size_t>(r)] = at;
    at += counts[static_cast<std::size_t>(r)];
  }
  if (static_cast<std::size_t>(at) > all_n) abort_processes(3);  // (the caller sized `all` wrongly)
  MPI_Allgatherv(data, mine, MPI_DOUBLE, all, counts.data(), starts.data(), MPI_DOUBLE, comm_of(comm_));
}

void Processes::all_to_all(const long* send, int per, long* recv) const {
  if (!distributed()) {
    std::copy_n(send, per, recv);
    return;
  }
  count_exchange(1, size_ - 1, static_cast<double>(size_ - 1) * per * sizeof(long));
  MPI_Alltoall(send, per, MPI_LONG, recv, per, MPI_LONG, comm_of(comm_));
}

}  // namespace skred
