// What each model folder declares about itself besides its update: its name in the scenario
// file, a one-line description, the table of its parameters (key, unit, default, allowed range,
// doc string; deal.II step-42 style declared parameters) and its strength for the relative yield
// function (Post eq. 66). A parser or documentation generator can read the tables; the scenario
// parser does not use them yet.
#pragma once
#include <limits>
#include <span>

namespace skred {

// One declared parameter. `min`/`max` bound the allowed values; *_open says whether the bound
// itself is excluded. `required` parameters have no default (default_value is NaN then; an
// optional one without a default is absent unless given). `example` is a typical valid value
// (for documentation and tests). Bounds that depend on another parameter (dilation <= friction,
// residual <= peak cohesion, e_max > e0) are stated in the doc string, the fixed part in min/max.
struct ParamSpec {
  const char* key;
  const char* unit;
  double default_value;
  double min, max;
  bool min_open, max_open;
  bool required;
  double example;
  const char* doc;
};

inline constexpr double kNoDefault = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();
// Largest modulus, strength or stress a parameter may have [Pa]: 1000 GPa, above any rock.
inline constexpr double kMaxStress = 1e12;

struct ModelInfo {
  const char* name;                   // as written in the scenario file, e.g. "mohr-coulomb"
  const char* description;            // one line
  std::span<const ParamSpec> params;  // the model's own keys (besides density, young, poisson)
};

// Mohr-Coulomb strength: friction angle phi [rad] and cohesion c [Pa]. Both NaN for a material
// without a strength (linear elastic), whose relative yield is then written as NaN.
struct MaterialStrength {
  double friction = std::numeric_limits<double>::quiet_NaN();
  double cohesion = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace skred
