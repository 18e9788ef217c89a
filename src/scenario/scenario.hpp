// The typed description of a simulation, parsed once from a TOML scenario file
// (docs/scenario.md documents every key). Solvers never see the parser, only these structs.
#pragma once
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/types.hpp"
#include "material/material.hpp"
#include "shape/interpolation.hpp"
#include "solver/boundary_side.hpp"
#include "solver/scheme.hpp"

namespace skred {

struct Rectangle { Vec<2> min, max; };
struct Polygon { std::vector<Vec<2>> vertices; };
struct Disc { Vec<2> center; double radius = 0.0; };
using Shape = std::variant<Rectangle, Polygon, Disc>;

// A sine-shaped initial velocity added to the body's uniform one (for mode shapes such as
// reference R1): v(x) += amplitude sin(2 pi (x[axis] - origin) / wavelength).
struct SineVelocity {
  Vec<2> amplitude = Vec<2>::Zero();  // [m/s]
  double wavelength = 0.0;            // [m]; 0: none
  int axis = 0;                       // 0: along x, 1: along y
  double origin = 0.0;                // [m]; where the sine is zero
};

struct Body {
  std::string name;
  Shape shape;
  int material = 0;              // index into Scenario::materials
  int particles_per_cell = 2;    // n: n x n material points per grid cell
  Vec<2> velocity = Vec<2>::Zero();  // initial velocity
  SineVelocity velocity_sine = {};   // added to `velocity`
};

// Initial stress from the weight of the soil above each point (Thesis eq. 5.6-5.7):
// sigma_yy = -g sum(rho h) over the column above, sigma_xx = sigma_zz = K0 sigma_yy.
enum class K0Rule {
  None,     // stress-free start (use an elastic incremental-gravity stage instead)
  Poisson,  // K0 = nu / (1 - nu), Thesis eq. 5.7
  Jaky,     // K0 = 1 - sin(phi), Post eq. 51 (materials without friction fall back to Poisson)
  Value     // a given K0
};
struct InitialStress {
  K0Rule rule = K0Rule::None;
  double k0 = 0.0;  // Value only
};

// A change of one material's strength for a stage (e.g. removing cohesion to trigger a
// slide, as Paper II does). Unset fields keep the material's value.
struct MaterialOverride {
  int material = 0;
  std::optional<double> friction, cohesion, dilation;  // [rad], [Pa], [rad]
};

// One stage of a staged analysis, run on the particles the previous stage left behind.
// Displacements, gravity work, strain energy and dissipation are measured from its start.
struct Stage {
  std::string name;
  double duration = 0.0;           // [s]; the stage ends at this time at the latest
  double gravity_ramp_time = 0.0;  // sine ramp of Thesis eq. 4.13 from the stage start; 0: at once
  bool elastic = false;            // hold every material linear elastic (equilibrium stage)
  double strength_reduction = 1.0; // c and tan(phi) divided by this factor
  std::vector<MaterialOverride> overrides;
  // The stage also ends once the mean speed (Thesis eq. 5.12) has stayed below rest_speed
  // for rest_time seconds (after the gravity ramp). rest_speed = 0 disables this.
  double rest_speed = 0.0;
  double rest_time = 0.0;
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
  InitialStress initial_stress;

  // Gravity: full acceleration vector g and the ramp time T of Thesis eq. 4.13
  // (0: gravity applied at once).
  Vec<2> gravity = Vec<2>::Zero();
  double gravity_ramp_time = 0.0;

  // Boundaries per grid side, in the order x_min, x_max, y_min, y_max.
  std::array<BoundarySide, 4> boundaries{};

  Interpolation interpolation = Interpolation::Gimp;
  int quadrature_points = 2;  // per direction, GimpQuadrature only (1, 2 or 3)
  StressScheme scheme = StressScheme::Averaged;

  // Stages in order; a file without [[stage]] tables gets one stage of length
  // solver.end_time with the [gravity] ramp. end_time is the sum of the durations.
  std::vector<Stage> stages;
  double end_time = 0.0;
  double time_step = 0.0;  // fixed time step; 0 means "from the CFL number"
  double cfl = 0.3;
  double pic_fraction = 0.0;  // PIC share of the particle velocity update (0: pure FLIP)

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
// The same with values replaced before validation (parameter sweeps): each key is a path
// such as "material[0].friction", "material[sand].cohesion" or "stage[1].duration".
Scenario parse_scenario(const std::string& text, const std::string& source,
                        const std::vector<std::pair<std::string, double>>& overrides);
// The text of a scenario file. Throws ScenarioError if it cannot be read.
std::string read_scenario_text(const std::string& path);

const char* to_string(BoundaryKind);
const char* to_string(Model);

}  // namespace skred
