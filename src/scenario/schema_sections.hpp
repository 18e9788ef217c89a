// Shared pieces of the scenario schema's section tables (schema.cpp, schema_run.cpp): the
// physical limits many keys share. Private to src/scenario.
#pragma once
#include <vector>

#include "scenario/schema.hpp"

namespace skred::schema::detail {

// Physical limits shared by many keys.
constexpr double kMaxLength = 1e7;      // m: coordinates and extents
constexpr double kMinCell = 1e-6;       // m
constexpr double kMaxTime = 1e7;        // s: durations, intervals, ramps
constexpr double kMinTimeStep = 1e-12;  // s
constexpr double kMaxTimeStep = 1e3;    // s
constexpr double kMaxSpeed = 1e4;       // m/s: initial velocities, rest speed
constexpr double kMaxGravity = 1e3;     // m/s^2 per component (100 g)

constexpr Range kCoordinate = Range::closed(-kMaxLength, kMaxLength);
constexpr Range kVelocity = Range::closed(-kMaxSpeed, kMaxSpeed);

// The sections of the model: top level, grid, materials, bodies, ground, contact, splitting
// (schema.cpp).
void add_model_sections(std::vector<Section>& s);
// The sections of the run: initial stress, gravity, boundaries, solver, stages, output
// (schema_run.cpp).
void add_run_sections(std::vector<Section>& s);

}  // namespace skred::schema::detail
