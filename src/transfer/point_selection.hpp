// Which points a map covers: all of them, or the points of one body (continuum, Paper III
// §C.2.7) in a run with contact.
#pragma once
#include <cstdint>

#include "core/inline.hpp"

namespace skred {

struct AllPoints {
  SKRED_INLINE bool operator()(long) const { return true; }
};
struct BodyPoints {
  const std::int16_t* __restrict body;
  int id;
  SKRED_INLINE bool operator()(long p) const { return body[p] == id; }
};

}  // namespace skred
