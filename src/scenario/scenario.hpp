// The typed description of a simulation, parsed once from a TOML scenario file
// (docs/scenario.md documents every key). Solvers never see the parser, only these structs.
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "core/types.hpp"
#include "material/material.hpp"
#include "scenario/output_fields.hpp"
#include "shape/interpolation.hpp"
#include "solver/boundary_side.hpp"
#include "solver/contact.hpp"
#include "solver/implicit_settings.hpp"
#include "solver/scheme.hpp"
#include "solver/splitting.hpp"
#include "solver/velocity_transfer.hpp"

namespace skred {

// 2D shapes (plane strain, in the x-y plane).
struct Rectangle {
  Vec<2> min, max;
};
struct Polygon {
  std::vector<Vec<2>> vertices;
};
struct Disc {
  Vec<2> center;
  double radius = 0.0;
};
// A profile y(x): a polyline with strictly increasing x (a surveyed cross-section, a line
// taken from a DEM), linear between its points.
struct Profile {
  std::vector<Vec<2>> points;
  double at(double x) const;  // y at x, for x within [front x, back x]
};
// The ground between two profiles, and below the ground surface if there is one:
// bottom(x) <= y < top(x) and y < surface(x), for front x <= x < back x of every profile.
struct Layer {
  Profile top, bottom;
  std::optional<Profile> surface;
};
using Shape = std::variant<Rectangle, Polygon, Disc, Layer>;

// 3D shapes (y vertical, x and z horizontal).
struct Box {
  Vec<3> min, max;
};
// A polygon in the x-y plane extruded along z over [z_min, z_max).
struct ExtrudedPolygon {
  Polygon section;
  double z_min = 0.0, z_max = 0.0;
};
// A circular cylinder: axis through `center` along the unit vector `axis`, end faces at
// center +- length/2 axis.
struct Cylinder {
  Vec<3> center = Vec<3>::Zero();
  Vec<3> axis = Vec<3>::UnitY();
  double radius = 0.0, length = 0.0;
};
struct Sphere {
  Vec<3> center;
  double radius = 0.0;
};
// An elevation raster on the scenario's horizontal plane: y(x, z), bilinear between the
// raster's cell centres and constant across its outer half cells (scenario/raster.hpp reads it).
struct ElevationRaster {
  std::string file;  // for messages
  int columns = 0, rows = 0;
  std::vector<double> heights;  // row-major from the file's first (upper) row; NaN: no data
  // Scenario (x, z) to fractional (column, row) of the cell centres:
  // column = to_cell[0] + to_cell[1] x + to_cell[2] z, row = to_cell[3] + to_cell[4] x + to_cell[5] z.
  std::array<double, 6> to_cell{};
  std::string crs;  // the coordinate reference system as WKT; empty: none given
  double at(double x, double z) const;
};
// The ground between two elevation rasters over the grid's horizontal extent, and below the
// ground surface if there is one: bottom(x, z) <= y < top(x, z) and y < surface(x, z).
struct Layer3 {
  std::shared_ptr<const ElevationRaster> top, bottom, surface;  // no bottom: the grid's bottom
  Vec<3> lo = Vec<3>::Zero(), hi = Vec<3>::Zero();              // its bounding box
};
using Shape3 = std::variant<Box, ExtrudedPolygon, Cylinder, Sphere, Layer3>;

template <int D>
using ShapeOf = std::conditional_t<D == 2, Shape, Shape3>;

// A sine-shaped initial velocity added to the body's uniform one (for mode shapes such as
// reference R1): v(x) += amplitude sin(2 pi (x[axis] - origin) / wavelength).
template <int D>
struct SineVelocityOf {
  Vec<D> amplitude = Vec<D>::Zero();  // [m/s]
  double wavelength = 0.0;            // [m]; 0: none
  int axis = 0;                       // 0: along x, 1: along y, 2: along z (3D)
  double origin = 0.0;                // [m]; where the sine is zero
};
using SineVelocity = SineVelocityOf<2>;

template <int D>
struct BodyOf {
  std::string name;
  ShapeOf<D> shape;
  int material = 0;            // index into Scenario::materials
  int particles_per_cell = 2;  // n: n^D material points per grid cell
  // 2D: the lattice of sub-cell centres turned by this angle [rad] about `lattice_centre`
  // (Acosta §6's rotated field of points, fig. 19); the points' domains stay grid-aligned.
  double lattice_rotation = 0.0;
  Vec<D> lattice_centre = Vec<D>::Zero();
  Vec<D> velocity = Vec<D>::Zero();      // initial velocity
  SineVelocityOf<D> velocity_sine = {};  // added to `velocity`
  bool split = false;                    // its points split when they deform too much (Thesis §3.4)
  // A rigid body moves with the constant `velocity` (zero: fixed), has no stress update and
  // takes part in contact (Paper III §C.2.7) as a partner of infinite mass.
  bool rigid = false;
  // A dilated continuum (Paper III §C.3.2): the id of the body whose points join this one
  // once they reach the maximum void ratio; it has no points at the start. -1: a body of the
  // file. These bodies follow the file's bodies (scenario/parser_dilation.cpp).
  int dilated_from = -1;
};
using Body = BodyOf<2>;
using Body3 = BodyOf<3>;

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
  // A trigger (Paper III §C.3: rainfall makes the clay heavier): the density the material's
  // points reach, over density_ramp_time from the stage start. Unlike the strength changes
  // it stays for the later stages.
  std::optional<double> density;   // [kg/m^3]
  double density_ramp_time = 0.0;  // [s]; 0: at once
};

// One stage of a staged analysis, run on the particles the previous stage left behind.
// Displacements, gravity work, strain energy and dissipation are measured from its start.
struct Stage {
  std::string name;
  double duration = 0.0;            // [s]; the stage ends at this time at the latest
  double gravity_ramp_time = 0.0;   // sine ramp of Thesis eq. 4.13 from the stage start; 0: at once
  bool elastic = false;             // hold every material linear elastic (equilibrium stage)
  double strength_reduction = 1.0;  // c and tan(phi) divided by this factor
  std::vector<MaterialOverride> overrides;
  // The stage also ends once the mean speed (Thesis eq. 5.12) has stayed below rest_speed
  // for rest_time seconds (after the gravity ramp). rest_speed = 0 disables this.
  double rest_speed = 0.0;
  double rest_time = 0.0;
  // Which speed the rest test (and the stage's stop time) reads: the points' own velocities
  // (Points, eq. 5.12), the velocity the material moves with (Material,
  // ExplicitSolver::material_mean_speed), the points' mean displacement over windows of
  // rest_time (Displacement, StageTracker::observe_window: a deposit ringing in place rests), or
  // Auto: Material where the points carry velocities the grid cannot see (pure FLIP, the affine
  // FLIP), Points otherwise (rest_measure_of).
  enum class RestMeasure { Auto, Points, Material, Displacement } rest_measure = RestMeasure::Auto;
  // The runout's threshold: the deposit's front is the outermost column it has raised by more
  // than this [m] (slide_measures.hpp). 0: half a cell.
  double runout_thickness = 0.0;
  // Local (non-viscous, Cundall type) damping alpha of the stage's grid update (0: off).
  double local_damping = 0.0;
  // Which integrator advances the stage (stage.integrator, else solver.integrator), and the
  // implicit integrator's settings for it ([implicit] with [stage.implicit] over it).
  IntegratorKind integrator = IntegratorKind::Explicit;
  ImplicitSettings implicit;
};

// Frictional contact between two bodies (Paper III §C.2.7): indices into the bodies, the
// Coulomb coefficient mu and the rule that detects contact. Pairs without an entry stay
// bonded (one velocity field).
struct ContactPair {
  int a = 0, b = 0;
  double friction = 0.0;
  ContactDetection detection = ContactDetection::Fill;  // `detection` (docs/method.md, "Contact")
};

// The xpic_period that velocity_transfer = "auto" gives a slide (docs/method.md, "The defaults").
inline constexpr double kAutoXpicPeriod = 2.0;

// What a scenario says apart from its geometry: the same in 2D and 3D.
struct ScenarioCommon {
  std::string source;  // path of the scenario file (for messages)
  std::string title;
  double cell_size = 0.0;

  std::vector<Material> materials;
  InitialStress initial_stress;
  double gravity_ramp_time = 0.0;  // ramp time T of Thesis eq. 4.13 (0: gravity at once)

  Interpolation interpolation = Interpolation::Gimp;
  int quadrature_points = 2;  // per direction, GimpQuadrature only (1, 2 or 3)
  StressScheme scheme = StressScheme::Averaged;

  // Stages in order; a file without [[stage]] tables gets one stage of length
  // solver.end_time with the [gravity] ramp. end_time is the sum of the durations.
  std::vector<Stage> stages;
  double end_time = 0.0;
  double time_step = 0.0;  // fixed time step; 0 means "from the CFL number"
  double cfl = 0.3;
  bool allow_unstable_time_step = false;  // a time_step above the stable step only warns
  double pic_fraction = 0.0;              // PIC share of the particle velocity update (0: pure FLIP)
  // Where bodies overlap: an error (false) or the later body's points only (true).
  bool later_body_wins = false;
  // Material-point splitting (Thesis §3.4; [splitting] and the bodies' `split` key);
  // splitting.body_splits is empty when no body splits.
  SplitSettings splitting;
  bool max_points_given = false;  // [splitting] max_points set (not 10 x the initial points)
  // The ground surface of a 2D scenario ([ground]); layers lie below it.
  std::optional<Profile> ground_surface;
  // A 2D scenario's [ground] section: the polyline on the map (easting, northing) along which
  // the profiles given as rasters are sampled, x the distance along it from its first vertex;
  // and the CRS (WKT) of the first of those rasters that gives one, with its file.
  std::vector<Vec<2>> ground_section;
  std::string section_crs, section_crs_file;
  // The ground surface of a 3D scenario ([ground] surface, a raster), and where the rasters' map
  // coordinates (easting, northing) of scenario x = z = 0 lie and the angle from east to +x.
  std::shared_ptr<const ElevationRaster> ground_raster;
  Vec<2> map_origin = Vec<2>::Zero();
  double map_rotation = 0.0;  // [rad], counter-clockwise seen from above

  // [[contact]] pairs; the master-slave hierarchy is the order of the [[body]] tables, each
  // dilated continuum right after its parent (Paper III §C.3.2). Holds the pairs of the
  // dilated continua too.
  std::vector<ContactPair> contacts;
  VelocityTransfer velocity_transfer = VelocityTransfer::Flip;  // solver.velocity_transfer
  bool transfer_by_default = false;    // velocity_transfer "auto" (absent): picked by the materials
  bool hyperelastic = false;           // solver.elastic_update = "hyperelastic"
  int xpic_order = 2;                  // solver.xpic_order (XPIC(m))
  double xpic_period = 0.0;            // solver.xpic_period, in crossing times h / (c + v0); 0: every step
  bool volumetric_averaging = false;   // solver.volumetric_strain = "cell-average"
  bool volumetric_by_default = false;  // volumetric_strain "auto" (absent): picked by the materials
  bool centre_shear = false;           // solver.shear_strain = "cell-centre" (Thesis §4.5)
  // solver.integrator: the stages' integrator unless a stage sets its own; [implicit]: the
  // implicit integrator's settings unless a stage's [stage.implicit] overrides them.
  IntegratorKind integrator = IntegratorKind::Explicit;
  ImplicitSettings implicit;
  // grid.geometry: plane strain, or axisymmetric (x the radius, y the axis; 2D only).
  Geometry geometry = Geometry::PlaneStrain;
  // [[pressure]]: pressures on bodies' faces that move with the material (implicit stages).
  std::vector<BoundaryPressure> pressures;
  // [[prescribed_velocity]]: grid nodes driven at a constant velocity (implicit stages).
  std::vector<PrescribedVelocity> prescribed;
  bool any_implicit() const {
    for (const Stage& st : stages)
      if (st.integrator == IntegratorKind::Implicit) return true;
    return false;
  }

  double output_interval = 0.0;  // simulated time between particle frames
  double series_interval = 0.0;  // simulated time between rows of series.csv
  // The particle fields of each frame (output.fields; scenario/output_fields.hpp), in the
  // order of output_fields::all(); and whether frames are zlib-compressed (output.compression).
  std::vector<std::string> output_fields = output_fields::defaults();
  bool output_compression = true;
  // 3D: the hazard maps (output.maps; run/hazard_maps.hpp) and the displacement past which a
  // point has moved (output.map_threshold; 0: half a cell).
  bool output_maps = true;
  double map_threshold = 0.0;
};

// A scenario in D dimensions (2: plane strain in x-y; 3: x, y, z with y vertical). The
// dimension is that of [grid] size (docs/scenario.md).
template <int D>
struct ScenarioOf : ScenarioCommon {
  static constexpr int dimension = D;
  // Background grid (Thesis §2.1): origin of the low corner, cells per axis (cell_size above).
  Vec<D> origin = Vec<D>::Zero();
  std::array<int, D> cells{};

  std::vector<BodyOf<D>> bodies;

  // Gravity: full acceleration vector g (ramp time above).
  Vec<D> gravity = Vec<D>::Zero();

  // Boundaries per grid side, in the order x_min, x_max, y_min, y_max (, z_min, z_max).
  std::array<BoundarySide, 2 * D> boundaries{};

  // Number of grid cells, the product over the axes.
  long cell_count() const {
    long n = 1;
    for (int c : cells) n *= c;
    return n;
  }
};
using Scenario = ScenarioOf<2>;
using Scenario3 = ScenarioOf<3>;
// A parsed file of either dimension.
using AnyScenario = std::variant<Scenario, Scenario3>;

// What a scenario of either dimension says apart from its geometry.
inline const ScenarioCommon& common_of(const AnyScenario& s) {
  return std::visit([](const auto& x) -> const ScenarioCommon& { return x; }, s);
}
inline ScenarioCommon& common_of(AnyScenario& s) {
  return std::visit([](auto& x) -> ScenarioCommon& { return x; }, s);
}

// A scenario that cannot be used. what() reads "FILE:LINE:COLUMN: key 'a.b': message".
struct ScenarioError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Parses and validates a 2D scenario file. Throws ScenarioError naming file, line and key
// (also for a 3D file, naming grid.size).
Scenario load_scenario(const std::string& path);
// The same from text in memory; `source` names it in messages.
Scenario parse_scenario(const std::string& text, const std::string& source);
// The same with values replaced before validation (parameter sweeps): each key is a path
// such as "material[0].friction", "material[sand].cohesion" or "stage[1].duration".
Scenario parse_scenario(const std::string& text, const std::string& source,
                        const std::vector<std::pair<std::string, double>>& overrides);
// A scenario file of either dimension (2D, or 3D when [grid] size has three components).
AnyScenario load_any_scenario(const std::string& path);
// `text_overrides` replace text values the same way (e.g. "solver.velocity_transfer").
AnyScenario parse_any_scenario(const std::string& text, const std::string& source,
                               const std::vector<std::pair<std::string, double>>& overrides = {},
                               const std::vector<std::pair<std::string, std::string>>& text_overrides = {});
// The text of a scenario file. Throws ScenarioError if it cannot be read.
std::string read_scenario_text(const std::string& path);

// The density of material m at the start of stage k: the last density change of an earlier
// stage, else the material's.
double density_at_stage_start(const ScenarioCommon& s, std::size_t k, int m);

// Whether the points keep velocities the grid cannot see (FLIP's null space): pure FLIP and the
// affine FLIP, which no filter or PIC share clears.
inline bool keeps_null_space(const ScenarioCommon& s) {
  return s.velocity_transfer == VelocityTransfer::Aflip ||
         (s.velocity_transfer == VelocityTransfer::Flip && s.pic_fraction == 0.0);
}

// What stage `st`'s rest test reads (Stage::rest_measure; "auto": the material's speed with
// pure FLIP and the affine FLIP, the points' otherwise). Never Auto.
inline Stage::RestMeasure rest_measure_of(const ScenarioCommon& s, const Stage& st) {
  if (st.rest_measure != Stage::RestMeasure::Auto) return st.rest_measure;
  return keeps_null_space(s) ? Stage::RestMeasure::Material : Stage::RestMeasure::Points;
}
const char* to_string(Stage::RestMeasure);

const char* to_string(BoundaryKind);
const char* to_string(Model);

}  // namespace skred
