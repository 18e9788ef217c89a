// The scenario schema: every section and key of a scenario file (see schema.hpp); the
// sections of the model here, those of the run in schema_run.cpp. The bounds
// are physical: they refuse values no soil, rock or laboratory model has (denormal densities,
// a 1e308 time step, 1e200 m/s), so a typo cannot start a run that does nothing or hangs.
#include "scenario/schema.hpp"

#include <cmath>
#include <stdexcept>

#include "material/elastic/info.hpp"
#include "material/mohr_coulomb/info.hpp"
#include "material/von_mises/info.hpp"
#include "scenario/schema_sections.hpp"

namespace skred::schema {

namespace detail {

namespace {

// A material model's own keys from its declared parameter table (material/<model>/info.hpp).
std::vector<Key> keys_of(std::span<const ParamSpec> params) {
  std::vector<Key> keys;
  for (const ParamSpec& p : params) {
    Default d = value(p.default_value);
    if (p.required)
      d = required();
    else if (!std::isfinite(p.default_value))
      d = none();
    keys.push_back({p.key, Type::Number, p.unit, d, Range{p.min, p.max, p.min_open, p.max_open}, "", p.doc});
  }
  return keys;
}

std::vector<Key> concat(std::vector<Key> a, const std::vector<Key>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

void add_model_sections(std::vector<Section>& s) {
  s.push_back(
      {"",
       "top-level",
       {
           {.name = "title",
            .type = Type::String,
            .def = derived("\"\""),
            .doc = "any text; used in summaries and output metadata"},
           {.name = "grid", .type = Type::Table, .doc = "the background grid"},
           {.name = "material", .type = Type::Tables, .doc = "at least one material"},
           {.name = "body", .type = Type::Tables, .doc = "at least one body"},
           {.name = "contact",
            .type = Type::Tables,
            .def = none("bodies bonded"),
            .doc = "frictional contact between pairs of bodies (Paper III §C.2.7)"},
           {.name = "body_overlap",
            .type = Type::Choice,
            .def = derived("\"error\""),
            .choices = "error|later-wins",
            .doc = "where two bodies overlap: an error naming both and the overlap area, or the "
                   "later body (in file order) keeps the points there"},
           {.name = "ground",
            .type = Type::Table,
            .def = none(),
            .doc = "the ground surface: a profile (2D) or a raster (3D)"},
           {.name = "splitting",
            .type = Type::Table,
            .def = none(),
            .doc = "constants of material-point splitting (Thesis §3.4) for the bodies with `split`"},
           {.name = "initial_stress", .type = Type::Table, .def = none(), .doc = "K0 initial stress"},
           {.name = "gravity", .type = Type::Table, .def = none(), .doc = "no gravity without it"},
           {.name = "boundary", .type = Type::Table, .def = none(), .doc = "all sides free without it"},
           {.name = "pressure",
            .type = Type::Tables,
            .def = none(),
            .doc = "pressures on faces of bodies that move with the material (implicit stages only)"},
           {.name = "prescribed_velocity",
            .type = Type::Tables,
            .def = none(),
            .doc = "grid nodes in a box driven at a constant velocity, with their force reported "
                   "(a footing pressed at a rate; implicit stages only)"},
           {.name = "solver",
            .type = Type::Table,
            .def = derived("required without [[stage]]"),
            .doc = "interpolation, scheme, time step, integrator"},
           {.name = "implicit",
            .type = Type::Table,
            .def = none(),
            .doc = "the implicit integrator's settings (stages with integrator = \"implicit\")"},
           {.name = "stage", .type = Type::Tables, .def = none(), .doc = "a staged analysis"},
           {.name = "output", .type = Type::Table, .def = none(), .doc = "output intervals"},
       }});
  s.push_back({"grid",
               "grid",
               {
                   {.name = "origin",
                    .type = Type::Vector,
                    .unit = "m",
                    .def = derived("[0, 0]"),
                    .range = kCoordinate,
                    .doc = "the low corner of the grid"},
                   {.name = "size",
                    .type = Type::Vector,
                    .unit = "m",
                    .range = Range::positive(kMaxLength),
                    .doc = "the extent along each axis"},
                   {.name = "cell_size",
                    .unit = "m",
                    .range = Range::closed(kMinCell, kMaxLength),
                    .doc = "h: cells are squares (cubes in 3D); see below"},
                   {.name = "geometry",
                    .type = Type::Choice,
                    .def = derived("\"plane-strain\""),
                    .choices = "plane-strain|axisymmetric",
                    .doc = "2D only: \"axisymmetric\" makes x the radius r (origin x >= 0) and y the axis; "
                           "masses and volumes are per radian; the axis x = 0 is a roller"},
               }});
  s.push_back({"material", "material",
               concat(
                   {
                       {.name = "name", .type = Type::String, .doc = "non-empty; unique among materials"},
                       {.name = "model",
                        .type = Type::Choice,
                        .choices = "linear-elastic|mohr-coulomb|tresca|von-mises",
                        .doc = "the constitutive model; each adds its own keys, below"},
                   },
                   keys_of(kElasticParamSpecs))});
  s.push_back({"material (mohr-coulomb)", "material-mohr-coulomb", keys_of(kMohrCoulombInfo.params)});
  s.push_back({"material (tresca)", "material-tresca", keys_of(kTrescaInfo.params)});
  s.push_back({"material (von-mises)", "material-von-mises", keys_of(kVonMisesInfo.params)});
  s.push_back(
      {"body",
       "body",
       {
           {.name = "name",
            .type = Type::String,
            .def = derived("\"body-I\" (I: the body's index)"),
            .doc = "names the body in messages and output"},
           {.name = "material", .type = Type::String, .doc = "the `name` of a [[material]]"},
           {.name = "particles_per_cell",
            .type = Type::Integer,
            .def = value(2),
            .range = Range::closed(1, 8),
            .doc = "n: n x n points per grid cell (n^3 in 3D)"},
           {.name = "lattice_rotation",
            .unit = "deg",
            .def = value(0),
            .range = Range::closed(-360, 360),
            .doc = "2D: the lattice of the points (the sub-cell centres) turned counter-clockwise by this "
                   "angle about `lattice_centre`, so the points no longer line up with the grid (Acosta "
                   "§6, fig. 19); their domains stay grid-aligned"},
           {.name = "lattice_centre",
            .type = Type::Vector,
            .unit = "m",
            .def = derived("the grid's origin"),
            .range = kCoordinate,
            .doc = "2D: the point the lattice turns about"},
           {.name = "velocity",
            .type = Type::Vector,
            .unit = "m/s",
            .def = derived("0"),
            .range = kVelocity,
            .doc = "initial velocity of every point"},
           {.name = "velocity_sine",
            .type = Type::Table,
            .def = none(),
            .doc = "adds a sine mode to the initial velocity (body.velocity_sine, below)"},
           {.name = "rigid",
            .type = Type::Boolean,
            .def = derived("false"),
            .doc = "a rigid body: moves with its constant `velocity` (0: fixed), no stress update, a "
                   "contact partner of infinite mass; its shape's outline gives the exact contact normal, "
                   "moving with it"},
           {.name = "split",
            .type = Type::Boolean,
            .def = derived("false"),
            .doc = "true: the body's points split when they deform too much (Thesis §3.4; [splitting])"},
           {.name = "dilation_continuum",
            .type = Type::Boolean,
            .def = derived("true in a run with [[contact]] for a deformable body whose material has the "
                           "dilation cut-off (mohr-coulomb with max_void_ratio), else false"),
            .doc = "Paper III §C.3.2: the body's points that reach max_void_ratio join a new body "
                   "\"NAME_dilated\", which slides on this one with mu = tan(phi) of its material and has "
                   "this body's contacts with the others (true turns contact on in a run without "
                   "[[contact]]); false: the cut-off only sets psi = 0"},
           {.name = "shape",
            .type = Type::Choice,
            .choices = "rectangle|polygon|disc|layer|box|cylinder|sphere",
            .doc =
                "2D: rectangle, polygon, disc, layer; 3D: box, polygon (extruded), cylinder, sphere, layer; "
                "each adds its own keys, below"},
       }});
  s.push_back({"body.velocity_sine",
               "body-velocity-sine",
               {
                   {.name = "amplitude",
                    .type = Type::Vector,
                    .unit = "m/s",
                    .range = kVelocity,
                    .doc = "a: adds a sin(2 pi (x[axis] - X0) / W) to the initial velocity"},
                   {.name = "wavelength", .unit = "m", .range = Range::positive(kMaxLength), .doc = "W"},
                   {.name = "axis",
                    .type = Type::Choice,
                    .def = derived("\"x\""),
                    .choices = "x|y|z",
                    .doc = "the coordinate the sine runs along (z in 3D only)"},
                   {.name = "origin", .unit = "m", .def = value(0), .range = kCoordinate, .doc = "X0"},
               }});
  s.push_back(
      {"body (rectangle)",
       "body-rectangle",
       {
           {.name = "min", .type = Type::Vector, .unit = "m", .range = kCoordinate, .doc = "the low corner"},
           {.name = "max",
            .type = Type::Vector,
            .unit = "m",
            .range = kCoordinate,
            .doc = "the high corner, greater than `min` in both components"},
       }});
  s.push_back({"body (polygon)",
               "body-polygon",
               {
                   {.name = "vertices",
                    .type = Type::Points,
                    .unit = "m",
                    .range = kCoordinate,
                    .doc = "[[x, y], ...]: at least 3 vertices, non-zero area, either orientation"},
               }});
  s.push_back(
      {"body (disc)",
       "body-disc",
       {
           {.name = "center", .type = Type::Vector, .unit = "m", .range = kCoordinate, .doc = "the centre"},
           {.name = "radius", .unit = "m", .range = Range::positive(kMaxLength), .doc = "the radius"},
       }});
  s.push_back({"ground",
               "ground",
               {
                   {.name = "surface",
                    .type = Type::Profile,
                    .unit = "m",
                    .doc = "the ground surface y(x), or y(x, z) in 3D; every layer lies below it"},
                   {.name = "section",
                    .type = Type::Points,
                    .unit = "m",
                    .def = none(),
                    .doc = "2D: [[easting, northing], ...], the map polyline along which the profiles "
                           "given as rasters (.asc, GeoTIFF: any file but .csv) are sampled; x is the "
                           "distance along it from its first vertex"},
                   {.name = "origin",
                    .type = Type::Vector,
                    .unit = "m",
                    .def = derived("[0, 0]"),
                    .doc = "3D: [easting, northing], the map point of scenario x = z = 0"},
                   {.name = "rotation",
                    .unit = "deg",
                    .def = value(0),
                    .range = Range::closed(-360, 360),
                    .doc = "3D: the angle from east to +x, counter-clockwise seen from above; z lies 90 "
                           "degrees clockwise from x (x east: z south)"},
               }});
  s.push_back({"body (layer)",
               "body-layer",
               {
                   {.name = "top",
                    .type = Type::Profile,
                    .unit = "m",
                    .def = derived("the ground surface"),
                    .doc = "the layer's upper boundary y(x) (3D: y(x, z)), clipped to the ground surface"},
                   {.name = "bottom",
                    .type = Type::Profile,
                    .unit = "m",
                    .def = derived("the grid's bottom"),
                    .doc = "its lower boundary y(x); the layer is bottom(x) <= y < top(x) where every "
                           "profile is defined (it pinches out where bottom >= top)"},
               }});
  s.push_back(
      {"body (box)",
       "body-box",
       {
           {.name = "min", .type = Type::Vector, .unit = "m", .range = kCoordinate, .doc = "the low corner"},
           {.name = "max",
            .type = Type::Vector,
            .unit = "m",
            .range = kCoordinate,
            .doc = "the high corner, greater than `min` in every component"},
       }});
  s.push_back({"body (extruded polygon)",
               "body-extruded",
               {
                   {.name = "vertices",
                    .type = Type::Points,
                    .unit = "m",
                    .range = kCoordinate,
                    .doc = "the x-y section: [[x, y], ...], at least 3 vertices, non-zero area"},
                   {.name = "z_min", .unit = "m", .range = kCoordinate, .doc = "the extrusion's low z"},
                   {.name = "z_max", .unit = "m", .range = kCoordinate, .doc = "its high z, > z_min"},
               }});
  s.push_back({"body (cylinder)",
               "body-cylinder",
               {
                   {.name = "center",
                    .type = Type::Vector,
                    .unit = "m",
                    .range = kCoordinate,
                    .doc = "the centre of the axis segment"},
                   {.name = "axis",
                    .type = Type::Vector,
                    .unit = "-",
                    .def = derived("[0, 1, 0]"),
                    .range = Range::closed(-1e6, 1e6),
                    .doc = "the axis direction (normalised; not zero)"},
                   {.name = "radius", .unit = "m", .range = Range::positive(kMaxLength), .doc = "the radius"},
                   {.name = "length",
                    .unit = "m",
                    .range = Range::positive(kMaxLength),
                    .doc = "the length along the axis"},
               }});
  s.push_back(
      {"body (sphere)",
       "body-sphere",
       {
           {.name = "center", .type = Type::Vector, .unit = "m", .range = kCoordinate, .doc = "the centre"},
           {.name = "radius", .unit = "m", .range = Range::positive(kMaxLength), .doc = "the radius"},
       }});
  s.push_back({"contact",
               "contact",
               {
                   {.name = "bodies",
                    .type = Type::BodyPair,
                    .doc = "the pair in contact; \"all\": every pair of bodies"},
                   {.name = "friction",
                    .unit = "-",
                    .range = Range::non_negative(10.0),
                    .doc = "the Coulomb coefficient mu of the pair (0: frictionless)"},
                   {.name = "detection",
                    .type = Type::Choice,
                    .def = derived("\"fill\""),
                    .choices = "fill|traction",
                    .doc = "when the approaching pair is in contact at a node: \"fill\", the two fill 0.8 of "
                           "the node's support (Nairn 2013); \"traction\", their nodal stresses' normal "
                           "traction is not tensile (Paper III §C.2.7; docs/method.md, \"Contact\")"},
               }});
  s.push_back({"splitting",
               "splitting",
               {
                   {.name = "alpha",
                    .unit = "-",
                    .def = value(2.0),
                    .range = Range::closed(1.1, 100.0),
                    .doc = "split when a diagonal component of F_split exceeds alpha (Thesis eq. 3.25)"},
                   {.name = "beta",
                    .unit = "-",
                    .def = value(0.5),
                    .range = Range::closed(0.01, 0.9),
                    .doc = "... or falls below beta"},
                   {.name = "gamma",
                    .unit = "-",
                    .def = value(1.0),
                    .range = Range::closed(0.1, 100.0),
                    .doc = "... or an off-diagonal component exceeds gamma in magnitude"},
                   {.name = "reference_after",
                    .type = Type::Integer,
                    .def = value(4),
                    .range = Range::closed(1, 20),
                    .doc = "a point split this many times gets the reference split of Thesis §3.4.2"},
                   {.name = "min_size",
                    .unit = "-",
                    .def = value(0.125),
                    .range = Range::closed(0.0, 1.0),
                    .doc = "no point is split into children smaller than a square (cube) of this "
                           "fraction of the cell size (0: no floor, the thesis as printed)"},
                   {.name = "max_points",
                    .type = Type::Integer,
                    .def = derived("10 x the initial points"),
                    .range = Range::closed(1, 1e9),
                    .doc = "no point splits once the run holds this many"},
                   {.name = "rebalance_above",
                    .unit = "-",
                    .def = value(1.1),
                    .range = Range::closed(1.0, 100.0),
                    .doc = "across processes: the points are shared out evenly again once the most a "
                           "process holds pass this multiple of the mean (split points land unevenly)"},
               }});
}

}  // namespace detail

namespace {

std::vector<Section> make_sections() {
  std::vector<Section> s;
  detail::add_model_sections(s);
  detail::add_run_sections(s);
  return s;
}

}  // namespace

const char* to_string(Type t) {
  switch (t) {
    case Type::Number: return "number";
    case Type::Integer: return "integer";
    case Type::Boolean: return "boolean";
    case Type::String: return "string";
    case Type::Choice: return "string";
    case Type::Vector: return "vector";
    case Type::Points: return "[[x, y], ...]";
    case Type::Table: return "table";
    case Type::Tables: return "tables";
    case Type::K0: return "string or number";
    case Type::Side: return "string or table";
    case Type::Profile:
      return "CSV file or [[x, y], ...]; a raster file along [ground] section (2D), or whole (3D)";
    case Type::BodyPair: return "[name, name] or \"all\"";
    case Type::Fields: return "string or [name, ...]";
  }
  return "?";
}

const Key* Section::find(std::string_view key) const {
  for (const Key& k : keys)
    if (key == k.name) return &k;
  return nullptr;
}

const Key& Section::at(std::string_view key) const {
  if (const Key* k = find(key)) return *k;
  throw std::logic_error("schema section '" + name + "' declares no key '" + std::string(key) + "'");
}

const std::vector<Section>& sections() {
  static const std::vector<Section> all = make_sections();
  return all;
}

const Section& section(std::string_view name) {
  for (const Section& s : sections())
    if (s.name == name) return s;
  throw std::logic_error("the scenario schema has no section '" + std::string(name) + "'");
}

std::vector<std::string> choices_of(const Key& k) {
  std::vector<std::string> out;
  std::string_view c = k.choices;
  while (!c.empty()) {
    const auto bar = c.find('|');
    out.emplace_back(c.substr(0, bar));
    if (bar == std::string_view::npos) break;
    c.remove_prefix(bar + 1);
  }
  return out;
}

}  // namespace skred::schema
