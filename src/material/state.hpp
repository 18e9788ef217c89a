// The per-point constitutive state lives with the particle storage (core/point_state.hpp):
// the particles own it, every model reads and writes it.
#pragma once
#include "core/point_state.hpp"
