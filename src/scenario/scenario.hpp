// The typed description of a simulation, parsed once from a TOML scenario file
// (docs/scenario.md documents every key). Solvers never see the parser, only these structs.
#pragma once
#include <array>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "core/types.hpp"
#include "material/material.hpp"

namespace skred {

enum class Interpolation { Linear, Gimp, GimpQuadrature, Bspline };
enum class StressScheme { USF, USL, Averaged };  // Thesis §4.4
enum class BoundaryKind { Free, Fixed, Roller, Friction };

struct BoundarySide {
  BoundaryKind kind = BoundaryKind::Free;
  double friction = 0.0;  // Coulomb coefficient mu (Thesis eq. 5.8), Friction only
};

struct Rectangle { Vec<2> min, max; };
struct Polygon { std::vector<Vec<2>> vertices; };
struct Disc { Vec<2> center; double radius = 0.0; };
using Shape = std::variant<Rectangle, Polygon, Disc>;

struct Body {
  std::string name;
  Shape shape;
  int material = 0;              // index into Scenario::materials
  int particles_per_cell = 2;    // n: n x n material points per grid cell
  Vec<2> velocity = Vec<2>::Zero();  // initial velocity
};

struct Scenario {
  std::string source;  // path of the scenario file (for messages)
  std::string title;

  // Background grid (Thesis §2.1): origin of the low corner, cells per axis, cell size.
  Vec<2> origin = Vec<2>::Zero();
  std::array<int, 2> cells{};
  double cell_size = 0.0;

  std::vector<Material> materials;
  std::vector<Body> bodies;

  // Gravity: full acceleration vector g and the ramp time T of Thesis eq. 4.13
  // (0: gravity applied at once).
  Vec<2> gravity = Vec<2>::Zero();
  double gravity_ramp_time = 0.0;

  // Boundaries per grid side, in the order x_min, x_max, y_min, y_max.
  std::array<BoundarySide, 4> boundaries{};

  Interpolation interpolation = Interpolation::Gimp;
  int quadrature_points = 2;  // per direction, GimpQuadrature only (1, 2 or 3)
  StressScheme scheme = StressScheme::Averaged;

  double end_time = 0.0;
  double time_step = 0.0;  // fixed time step; 0 means "from the CFL number"
  double cfl = 0.3;

  double output_interval = 0.0;  // simulated time between particle frames
  double series_interval = 0.0;  // simulated time between rows of series.csv
};

// A scenario that cannot be used. what() reads "FILE:LINE:COLUMN: key 'a.b': message".
struct ScenarioError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Parses and validates a scenario file. Throws ScenarioError naming file, line and key.
Scenario load_scenario(const std::string& path);
// The same from text in memory; `source` names it in messages.
Scenario parse_scenario(const std::string& text, const std::string& source);

const char* to_string(Interpolation);
const char* to_string(StressScheme);
const char* to_string(BoundaryKind);

}  // namespace skred
