// What this process has exchanged with the others (processes.hpp), counted by the calls that
// communicate, in either build (processes.cpp with MPI, processes_alone.cpp without).
#include "parallel/processes.hpp"

namespace skred {

namespace {
Exchanged traffic;  // (only the main thread communicates)
}  // namespace

Exchanged exchanged() { return traffic; }

void count_exchange(long calls, long messages, double bytes, long forests) {
  traffic.forests += forests;
  traffic.calls += calls;
  traffic.messages += messages;
  traffic.bytes += bytes;
}

}  // namespace skred
