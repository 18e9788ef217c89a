// Scenario file parser: TOML text -> validated Scenario. The schema is documented in
// docs/scenario.md; keep the two in step.
#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "scenario/build.hpp"
#include "scenario/scenario.hpp"
#include "scenario/toml_reader.hpp"

namespace skred {

const char* to_string(Model m) {
  switch (m) {
    case Model::LinearElastic: return "linear-elastic";
    case Model::MohrCoulomb: return "mohr-coulomb";
    case Model::Tresca: return "tresca";
    case Model::VonMises: return "von-mises";
  }
  return "?";
}

const char* to_string(BoundaryKind b) {
  switch (b) {
    case BoundaryKind::Free: return "free";
    case BoundaryKind::Fixed: return "fixed";
    case BoundaryKind::Roller: return "roller";
    case BoundaryKind::Friction: return "friction";
  }
  return "?";
}

namespace {

using scenario_detail::Choices;
using scenario_detail::fail;
using scenario_detail::Location;
using scenario_detail::location_of;
using scenario_detail::node_vec2;
using scenario_detail::Range;
using scenario_detail::TableReader;

constexpr int kMaxCells = 100000;
constexpr int kMaxParticlesPerCell = 8;

const char* axis_name(int d) { return d == 0 ? "x" : "y"; }

void parse_grid(const TableReader& root, Scenario& s) {
  const TableReader g = *root.table("grid", true);
  g.allow_only({"origin", "size", "cell_size"});
  s.origin = g.vec2("origin", Vec<2>::Zero());
  const Vec<2> size = g.vec2("size");
  for (int d = 0; d < 2; ++d)
    if (!(size[d] > 0.0))
      g.fail_at("size", fmt::format("the {} extent must be > 0, got {}", axis_name(d), size[d]));
  const double h = g.number("cell_size", Range::positive());
  for (int d = 0; d < 2; ++d) {
    const double ratio = size[d] / h;
    if (ratio < 0.5)
      g.fail_at("cell_size", fmt::format("cell_size {} is larger than the grid size {} along {}",
                                         h, size[d], axis_name(d)));
    if (ratio > kMaxCells + 0.5)
      g.fail_at("cell_size", fmt::format("gives {:.0f} cells along {}; at most {} are allowed",
                                         ratio, axis_name(d), kMaxCells));
    const double n = std::round(ratio);
    if (std::abs(n * h - size[d]) > 1e-9 * size[d])
      g.fail_at("size", fmt::format("the {} extent {} is not a whole multiple of cell_size {} "
                                    "({} cells)", axis_name(d), size[d], h, ratio));
    s.cells[static_cast<std::size_t>(d)] = static_cast<int>(n);
  }
  s.cell_size = h;
}

constexpr double kDeg = M_PI / 180.0;

// Strength keys of the plastic models (Thesis eq. 5.1-5.4; Paper III §C.3.2; Acosta §3.2).
void parse_strength(const TableReader& t, Material& m) {
  switch (m.model) {
    case Model::LinearElastic:
      t.allow_only({"name", "model", "density", "young", "poisson"});
      return;
    case Model::MohrCoulomb: {
      t.allow_only({"name", "model", "density", "young", "poisson", "friction", "cohesion",
                    "dilation", "tension_cutoff", "initial_void_ratio", "max_void_ratio"});
      MohrCoulombParams& mc = m.mohr_coulomb;
      const double phi_deg = t.number("friction", Range{0.0, 90.0, false, true});
      mc.friction = phi_deg * kDeg;
      mc.cohesion = t.number("cohesion", Range::non_negative());
      if (mc.friction == 0.0 && mc.cohesion == 0.0)
        t.fail_at("cohesion", "a Mohr-Coulomb material needs friction > 0 or cohesion > 0");
      mc.dilation = t.number("dilation", Range::closed(0.0, phi_deg), 0.0) * kDeg;
      if (t.has("tension_cutoff"))
        mc.tension_cutoff = t.number("tension_cutoff", Range::non_negative());
      if (t.has("initial_void_ratio") != t.has("max_void_ratio"))
        t.fail_at(t.has("max_void_ratio") ? "max_void_ratio" : "initial_void_ratio",
                  "the dilation cut-off needs both initial_void_ratio and max_void_ratio");
      if (t.has("max_void_ratio")) {
        mc.initial_void_ratio = t.number("initial_void_ratio", Range::positive());
        mc.max_void_ratio = t.number("max_void_ratio", Range{mc.initial_void_ratio,
                                                             INFINITY, true, false});
      }
      return;
    }
    case Model::Tresca:
      t.allow_only({"name", "model", "density", "young", "poisson", "cohesion"});
      m.mohr_coulomb.cohesion = t.number("cohesion", Range::positive());
      return;
    case Model::VonMises: {
      t.allow_only({"name", "model", "density", "young", "poisson", "cohesion",
                    "residual_cohesion", "softening_modulus"});
      VonMisesParams& vm = m.von_mises;
      vm.cohesion_peak = t.number("cohesion", Range::positive());
      vm.cohesion_residual = t.number("residual_cohesion", Range::closed(0.0, vm.cohesion_peak),
                                      vm.cohesion_peak);
      vm.softening_modulus = t.number("softening_modulus", Range{-INFINITY, 0.0, false, false}, 0.0);
      return;
    }
  }
}

void parse_materials(const TableReader& root, Scenario& s) {
  const auto tables = root.array_of_tables("material");
  if (tables.empty())
    fail(s.source, root.where("material"), "material",
         "at least one [[material]] table is required");
  std::map<std::string, Location> seen;
  for (const auto& t : tables) {
    Material m;
    m.name = t.string("name");
    if (m.name.empty()) t.fail_at("name", "must not be empty");
    if (const auto it = seen.find(m.name); it != seen.end())
      t.fail_at("name", fmt::format("duplicate material name \"{}\" (first defined on line {})",
                                    m.name, it->second.line));
    seen.emplace(m.name, t.where("name"));
    const auto M = [](Model x) { return std::pair{to_string(x), x}; };
    m.model = t.choice<Model>("model", {M(Model::LinearElastic), M(Model::MohrCoulomb),
                                        M(Model::Tresca), M(Model::VonMises)});
    parse_strength(t, m);
    m.density = t.number("density", Range::positive());
    m.elastic.young = t.number("young", Range::positive());
    m.elastic.poisson = t.number("poisson", Range{0.0, 0.5, false, true});
    s.materials.push_back(std::move(m));
  }
}

// Index of the material called `name`, or a message listing the defined ones.
int material_index(const TableReader& t, std::string_view key, const Scenario& s) {
  const std::string name = t.string(key);
  for (std::size_t m = 0; m < s.materials.size(); ++m)
    if (s.materials[m].name == name) return static_cast<int>(m);
  std::string names;
  for (const auto& m : s.materials) names += fmt::format("{}\"{}\"", names.empty() ? "" : ", ", m.name);
  t.fail_at(key, fmt::format("no [[material]] is named \"{}\"; defined: {}", name, names));
}

// High corner of the grid and the tolerance for "inside the grid" tests.
Vec<2> grid_high(const Scenario& s) { return s.origin + s.cell_size * Vec<2>(s.cells[0], s.cells[1]); }
double grid_tolerance(const Scenario& s) { return 1e-9 * (grid_high(s) - s.origin).maxCoeff(); }

bool inside_grid(const Scenario& s, const Vec<2>& x) {
  const double tol = grid_tolerance(s);
  return (x.array() >= s.origin.array() - tol).all() && (x.array() <= grid_high(s).array() + tol).all();
}

std::string grid_bounds(const Scenario& s) {
  const Vec<2> hi = grid_high(s);
  return fmt::format("[{}, {}] x [{}, {}]", s.origin[0], hi[0], s.origin[1], hi[1]);
}

// Checks that point x lies within the grid; `what` names it in the message.
void check_inside(const TableReader& t, std::string_view key, const Scenario& s, const Vec<2>& x,
                  const std::string& what) {
  if (!inside_grid(s, x))
    t.fail_at(key, fmt::format("{} ({}, {}) lies outside the grid {}", what, x[0], x[1],
                               grid_bounds(s)));
}

Shape parse_rectangle(const TableReader& b, const Scenario& s) {
  b.allow_only({"name", "material", "particles_per_cell", "velocity", "velocity_sine", "shape",
                 "min", "max"});
  Rectangle r{b.vec2("min"), b.vec2("max")};
  if (!(r.max[0] > r.min[0] && r.max[1] > r.min[1]))
    b.fail_at("max", fmt::format("max ({}, {}) must exceed min ({}, {}) in both components",
                                 r.max[0], r.max[1], r.min[0], r.min[1]));
  check_inside(b, "min", s, r.min, "min corner");
  check_inside(b, "max", s, r.max, "max corner");
  return r;
}

Shape parse_polygon(const TableReader& b, const Scenario& s) {
  b.allow_only({"name", "material", "particles_per_cell", "velocity", "velocity_sine", "shape",
                 "vertices"});
  if (!b.has("vertices")) b.fail_missing("vertices");
  const auto* arr = b.find("vertices")->as_array();
  if (!arr) b.fail_type("vertices", "an array of [x, y] pairs");
  if (arr->size() < 3)
    b.fail_at("vertices", fmt::format("a polygon needs at least 3 vertices, got {}", arr->size()));
  Polygon p;
  for (std::size_t k = 0; k < arr->size(); ++k) {
    const std::string key = fmt::format("{}[{}]", b.key("vertices"), k);
    const Vec<2> v = node_vec2(*arr->get(k), b.source(), key, b.where("vertices"));
    if (!inside_grid(s, v))
      fail(b.source(), location_of(arr->get(k)->source(), b.where("vertices")), key,
           fmt::format("vertex ({}, {}) lies outside the grid {}", v[0], v[1], grid_bounds(s)));
    p.vertices.push_back(v);
  }
  Vec<2> lo = p.vertices[0], hi = p.vertices[0];
  for (const auto& v : p.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const Vec<2> span = hi - lo;
  if (!(std::abs(polygon_area(p)) > 1e-12 * span.squaredNorm()))
    b.fail_at("vertices", "the polygon has zero area");
  return p;
}

Shape parse_disc(const TableReader& b, const Scenario& s) {
  b.allow_only({"name", "material", "particles_per_cell", "velocity", "velocity_sine", "shape",
                 "center", "radius"});
  Disc c{b.vec2("center"), b.number("radius", Range::positive())};
  check_inside(b, "center", s, c.center, "centre");
  const Vec<2> r = Vec<2>::Constant(c.radius);
  if (!inside_grid(s, c.center - r) || !inside_grid(s, c.center + r))
    b.fail_at("radius", fmt::format("the disc of radius {} around ({}, {}) extends outside the "
                                    "grid {}", c.radius, c.center[0], c.center[1],
                                    grid_bounds(s)));
  return c;
}

void parse_bodies(const TableReader& root, Scenario& s) {
  const auto tables = root.array_of_tables("body");
  if (tables.empty())
    fail(s.source, root.where("body"), "body", "at least one [[body]] table is required");
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const TableReader& t = tables[i];
    enum class Kind { Rectangle, Polygon, Disc };
    const Kind kind = t.choice<Kind>(
        "shape", {{"rectangle", Kind::Rectangle}, {"polygon", Kind::Polygon}, {"disc", Kind::Disc}});
    Body b;
    switch (kind) {
      case Kind::Rectangle: b.shape = parse_rectangle(t, s); break;
      case Kind::Polygon: b.shape = parse_polygon(t, s); break;
      case Kind::Disc: b.shape = parse_disc(t, s); break;
    }
    b.name = t.string("name", fmt::format("body-{}", i));
    b.material = material_index(t, "material", s);
    b.particles_per_cell = static_cast<int>(t.integer("particles_per_cell", 1, kMaxParticlesPerCell, 2));
    b.velocity = t.vec2("velocity", Vec<2>::Zero());
    if (const auto vs = t.table("velocity_sine", false)) {
      vs->allow_only({"amplitude", "wavelength", "axis", "origin"});
      b.velocity_sine.amplitude = vs->vec2("amplitude");
      b.velocity_sine.wavelength = vs->number("wavelength", Range::positive());
      b.velocity_sine.axis = vs->choice<int>("axis", {{"x", 0}, {"y", 1}}, 0);
      b.velocity_sine.origin = vs->number("origin", Range::any(), 0.0);
    }
    if (!has_points(s, b))
      t.fail_at("shape", fmt::format("body \"{}\" contains no material point: it covers no "
                                     "sub-cell centre (spacing {} m); enlarge it, refine the grid "
                                     "or raise particles_per_cell", b.name,
                                     s.cell_size / b.particles_per_cell));
    s.bodies.push_back(std::move(b));
  }
}

void parse_gravity(const TableReader& root, Scenario& s) {
  const auto g = root.table("gravity", false);
  if (!g) return;
  g->allow_only({"acceleration", "ramp_time"});
  s.gravity = g->vec2("acceleration", Vec<2>::Zero());
  s.gravity_ramp_time = g->number("ramp_time", Range::non_negative(), 0.0);
}

BoundarySide parse_side(const TableReader& bt, std::string_view side) {
  constexpr const char* allowed =
      "\"free\", \"fixed\", \"roller\", { type = \"friction\", friction = MU }";
  const toml::node& n = *bt.find(side);
  if (n.is_string()) {
    const Choices<BoundaryKind> choices = {{"free", BoundaryKind::Free},
                                           {"fixed", BoundaryKind::Fixed},
                                           {"roller", BoundaryKind::Roller}};
    const std::string v = bt.string(side);
    if (v == to_string(BoundaryKind::Friction))
      bt.fail_at(side, "\"friction\" needs a coefficient: write { type = \"friction\", "
                       "friction = 0.6 }");
    for (const auto& [name, kind] : choices)
      if (v == name) return BoundarySide{kind, 0.0};
    bt.fail_at(side, fmt::format("unknown value \"{}\"; allowed values: {}", v, allowed));
  }
  if (!n.is_table()) bt.fail_type(side, "a string or an inline table { type = ... }");
  const TableReader t = *bt.table(side, true);
  const BoundaryKind kind = t.choice<BoundaryKind>(
      "type", {{"free", BoundaryKind::Free}, {"fixed", BoundaryKind::Fixed},
               {"roller", BoundaryKind::Roller}, {"friction", BoundaryKind::Friction}});
  if (kind != BoundaryKind::Friction) {
    if (t.has("friction"))
      t.fail_at("friction", "only allowed together with type = \"friction\"");
    t.allow_only({"type"});
    return BoundarySide{kind, 0.0};
  }
  t.allow_only({"type", "friction"});
  return BoundarySide{kind, t.number("friction", Range::non_negative())};
}

void parse_boundary(const TableReader& root, Scenario& s) {
  const auto b = root.table("boundary", false);
  if (!b) return;
  b->allow_only({"x_min", "x_max", "y_min", "y_max"});
  const char* sides[4] = {"x_min", "x_max", "y_min", "y_max"};
  for (std::size_t k = 0; k < 4; ++k)
    if (b->has(sides[k])) s.boundaries[k] = parse_side(*b, sides[k]);
}

void parse_solver(const TableReader& root, Scenario& s) {
  // [solver] may be left out when [[stage]] tables give the end time.
  static const toml::table empty;
  const TableReader t = root.table("solver", !root.has("stage"))
                            .value_or(TableReader(empty, "solver", s.source));
  t.allow_only({"interpolation", "quadrature_points", "scheme", "end_time", "time_step", "cfl",
                "pic_fraction"});
  const auto I = [](Interpolation i) { return std::pair{to_string(i), i}; };
  s.interpolation = t.choice<Interpolation>(
      "interpolation", {I(Interpolation::Linear), I(Interpolation::Gimp),
                        I(Interpolation::GimpQuadrature), I(Interpolation::Bspline)},
      Interpolation::Gimp);
  s.quadrature_points = static_cast<int>(t.integer("quadrature_points", 1, 3, 2));
  const auto S = [](StressScheme x) { return std::pair{to_string(x), x}; };
  s.scheme = t.choice<StressScheme>(
      "scheme", {S(StressScheme::USF), S(StressScheme::USL), S(StressScheme::Averaged)},
      StressScheme::Averaged);
  // With [[stage]] tables the stage durations give the end time (parse_stages).
  if (root.has("stage")) {
    if (t.has("end_time"))
      t.fail_at("end_time", "the [[stage]] durations set the end time; remove solver.end_time");
  } else {
    s.end_time = t.number("end_time", Range::positive());
  }
  s.time_step = t.has("time_step") ? t.number("time_step", Range::positive()) : 0.0;
  s.cfl = t.number("cfl", Range{0.0, 1.0, true, false}, 0.3);
  s.pic_fraction = t.number("pic_fraction", Range::closed(0.0, 1.0), 0.0);
}

void parse_initial_stress(const TableReader& root, Scenario& s) {
  const auto t = root.table("initial_stress", false);
  if (!t) return;
  t->allow_only({"k0"});
  InitialStress& is = s.initial_stress;
  const toml::node* n = t->find("k0");
  if (!n) t->fail_missing("k0");
  if (n->is_number()) {
    is.rule = K0Rule::Value;
    is.k0 = t->number("k0", Range::closed(0.0, 10.0));
    return;
  }
  if (!n->is_string()) t->fail_type("k0", "\"poisson\", \"jaky\" or a number");
  is.rule = t->choice<K0Rule>("k0", {{"poisson", K0Rule::Poisson}, {"jaky", K0Rule::Jaky}});
}

MaterialOverride parse_override(const TableReader& t, const Scenario& s) {
  t.allow_only({"name", "friction", "cohesion", "dilation"});
  MaterialOverride o;
  o.material = material_index(t, "name", s);
  const Material& m = s.materials[static_cast<std::size_t>(o.material)];
  const bool mc = m.model == Model::MohrCoulomb;
  if (!mc && (t.has("friction") || t.has("dilation")))
    t.fail_at(t.has("friction") ? "friction" : "dilation",
              fmt::format("material \"{}\" is {}; only mohr-coulomb has a friction or dilation "
                          "angle", m.name, to_string(m.model)));
  if (!m.plastic() && t.has("cohesion"))
    t.fail_at("cohesion", fmt::format("material \"{}\" is linear-elastic and has no cohesion", m.name));
  if (t.has("friction")) o.friction = t.number("friction", Range{0.0, 90.0, false, true}) * kDeg;
  if (t.has("cohesion"))
    o.cohesion = t.number("cohesion", m.model == Model::MohrCoulomb ? Range::non_negative()
                                                                    : Range::positive());
  if (t.has("dilation")) o.dilation = t.number("dilation", Range{0.0, 90.0, false, true}) * kDeg;
  const double phi = o.friction.value_or(m.mohr_coulomb.friction);
  if (o.dilation.value_or(m.mohr_coulomb.dilation) > phi + 1e-12)
    t.fail_at(o.dilation ? "dilation" : "friction",
              "the dilation angle must not exceed the friction angle");
  if (mc && phi == 0.0 && o.cohesion.value_or(m.mohr_coulomb.cohesion) == 0.0)
    t.fail_at(o.cohesion ? "cohesion" : "friction", "the material would have no strength left");
  return o;
}

void parse_stages(const TableReader& root, Scenario& s) {
  const auto tables = root.array_of_tables("stage");
  if (tables.empty()) {  // one implicit stage: [solver] end_time with the [gravity] ramp
    Stage st;
    st.name = "run";
    st.duration = s.end_time;
    st.gravity_ramp_time = s.gravity_ramp_time;
    s.stages.push_back(st);
    return;
  }
  if (s.gravity_ramp_time > 0)
    fail(s.source, root.table("gravity", true)->where("ramp_time"), "gravity.ramp_time",
         "with [[stage]] tables give the ramp per stage (stage.gravity_ramp_time)");
  s.end_time = 0.0;
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const TableReader& t = tables[i];
    t.allow_only({"name", "duration", "gravity_ramp_time", "elastic", "strength_reduction",
                  "material", "rest_speed", "rest_time"});
    Stage st;
    st.name = t.string("name", fmt::format("stage-{}", i));
    st.duration = t.number("duration", Range::positive());
    st.gravity_ramp_time = t.number("gravity_ramp_time", Range::non_negative(), 0.0);
    if (st.gravity_ramp_time > st.duration)
      t.fail_at("gravity_ramp_time", fmt::format("the ramp ({} s) is longer than the stage ({} s)",
                                                 st.gravity_ramp_time, st.duration));
    if (t.has("elastic")) {
      const auto v = t.find("elastic")->value<bool>();
      if (!v) t.fail_type("elastic", "a boolean (true or false)");
      st.elastic = *v;
    }
    st.strength_reduction = t.number("strength_reduction", Range{1.0, 100.0, false, false}, 1.0);
    for (const auto& m : t.array_of_tables("material")) st.overrides.push_back(parse_override(m, s));
    st.rest_speed = t.number("rest_speed", Range::non_negative(), 0.0);
    if (t.has("rest_time") && st.rest_speed == 0.0)
      t.fail_at("rest_time", "only allowed together with rest_speed > 0");
    st.rest_time = t.number("rest_time", Range::positive(), 0.0);
    if (st.rest_speed > 0.0 && !t.has("rest_time")) t.fail_missing("rest_time");
    s.end_time += st.duration;
    s.stages.push_back(std::move(st));
  }
}

void parse_output(const TableReader& root, Scenario& s) {
  const auto o = root.table("output", false);
  s.output_interval = s.end_time / 20.0;
  if (o) {
    o->allow_only({"interval", "series_interval"});
    s.output_interval = o->number("interval", Range::positive(), s.output_interval);
  }
  s.series_interval = s.output_interval / 10.0;
  if (o) s.series_interval = o->number("series_interval", Range::positive(), s.series_interval);
}

}  // namespace

namespace {

toml::table parse_toml(const std::string& text, const std::string& source) {
  try {
    return toml::parse(std::string_view(text), std::string_view(source));
  } catch (const toml::parse_error& e) {
    const Location at = location_of(e.source(), Location{1, 1});
    throw ScenarioError(fmt::format("{}:{}:{}: syntax error: {}", source, at.line, at.column,
                                    e.description()));
  }
}

// Sets the value at a key path such as "material[0].friction" or "material[sand].friction"
// (an array element chosen by its name key) or "stage[1].material[0].cohesion".
void set_key(toml::table& doc, const std::string& path, double value, const std::string& source) {
  const auto bad = [&](const std::string& why) {
    throw ScenarioError(fmt::format("{}: key '{}': {}", source, path, why));
  };
  toml::table* table = &doc;
  std::size_t pos = 0;
  while (true) {
    const std::size_t dot = path.find('.', pos);
    std::string part = path.substr(pos, dot == std::string::npos ? std::string::npos : dot - pos);
    std::string index;
    if (const auto open = part.find('['); open != std::string::npos) {
      if (part.back() != ']') bad("expected NAME[INDEX] in the key path");
      index = part.substr(open + 1, part.size() - open - 2);
      part.resize(open);
    }
    if (part.empty()) bad("empty component in the key path");
    if (dot == std::string::npos) {
      if (!index.empty()) bad("the last component must name a value, not an array element");
      const toml::node* old = table->get(part);
      if (old && old->is_integer() && value == std::floor(value))
        table->insert_or_assign(part, static_cast<std::int64_t>(value));
      else
        table->insert_or_assign(part, value);
      return;
    }
    toml::node* next = table->get(part);
    if (!next) bad(fmt::format("'{}' is not in the scenario", part));
    if (!index.empty()) {
      toml::array* arr = next->as_array();
      if (!arr) bad(fmt::format("'{}' is not an array of tables", part));
      toml::node* element = nullptr;
      char* end = nullptr;
      const long k = std::strtol(index.c_str(), &end, 10);
      if (end && *end == '\0' && k >= 0 && static_cast<std::size_t>(k) < arr->size()) {
        element = arr->get(static_cast<std::size_t>(k));
      } else {
        for (auto& e : *arr)
          if (auto* t = e.as_table(); t && t->get("name") && t->get("name")->value<std::string>() == index)
            element = &e;
      }
      if (!element) bad(fmt::format("'{}' has no element '{}'", part, index));
      next = element;
    }
    table = next->as_table();
    if (!table) bad(fmt::format("'{}' is not a table", part));
    pos = dot + 1;
  }
}

Scenario parse_document(const toml::table& doc, const std::string& source);

}  // namespace

Scenario parse_scenario(const std::string& text, const std::string& source) {
  return parse_document(parse_toml(text, source), source);
}

Scenario parse_scenario(const std::string& text, const std::string& source,
                        const std::vector<std::pair<std::string, double>>& overrides) {
  toml::table doc = parse_toml(text, source);
  for (const auto& [key, value] : overrides) set_key(doc, key, value, source);
  return parse_document(doc, source);
}

namespace {

Scenario parse_document(const toml::table& doc, const std::string& source) {
  const TableReader root(doc, "", source);
  root.allow_only({"title", "grid", "material", "body", "initial_stress", "gravity", "boundary",
                   "solver", "stage", "output"});
  Scenario s;
  s.source = source;
  s.title = root.string("title", std::string());
  parse_grid(root, s);
  parse_materials(root, s);
  parse_bodies(root, s);
  parse_gravity(root, s);
  parse_boundary(root, s);
  parse_initial_stress(root, s);
  parse_solver(root, s);
  parse_stages(root, s);
  parse_output(root, s);
  return s;
}

}  // namespace

std::string read_scenario_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ScenarioError(fmt::format("{}: cannot open scenario file: {}", path,
                                    std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ScenarioError(fmt::format("{}: cannot read scenario file", path));
  return text.str();
}

Scenario load_scenario(const std::string& path) { return parse_scenario(read_scenario_text(path), path); }

}  // namespace skred
