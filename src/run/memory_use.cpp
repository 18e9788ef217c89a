#include "run/memory_use.hpp"

#include <fstream>
#include <string>
#if defined(__GLIBC__)  // (defined by the headers above)
#include <malloc.h>
#endif

namespace skred {

namespace {

// The value of `key` (e.g. "VmHWM:", in kB) in /proc/self/status, in bytes; 0 if absent.
double status_bytes(const char* key) {
  std::ifstream f("/proc/self/status");
  std::string k;
  while (f >> k) {
    if (k == key) {
      double kb = 0;
      f >> kb;
      return kb * 1024.0;
    }
    std::getline(f, k);
  }
  return 0.0;
}

}  // namespace

double peak_rss_bytes() { return status_bytes("VmHWM:"); }
double current_rss_bytes() { return status_bytes("VmRSS:"); }

bool reset_peak_rss() {
  std::ofstream f("/proc/self/clear_refs");
  f << "5";
  f.flush();
  return static_cast<bool>(f);
}

void release_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace skred
