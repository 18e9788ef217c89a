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
#include "scenario/parse_transfer.hpp"
#include "scenario/parser_detail.hpp"
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

namespace scenario_detail {

// Index of the material called `name`, or a message listing the defined ones.
int material_index(const TableReader& t, std::string_view key, const ScenarioCommon& s) {
  const std::string name = t.string(key);
  for (std::size_t m = 0; m < s.materials.size(); ++m)
    if (s.materials[m].name == name) return static_cast<int>(m);
  std::string names;
  for (const auto& m : s.materials) names += fmt::format("{}\"{}\"", names.empty() ? "" : ", ", m.name);
  t.fail_at(key, fmt::format("no [[material]] is named \"{}\"; defined: {}", name, names));
}

}  // namespace scenario_detail

namespace {

using scenario_detail::fail;
using scenario_detail::Location;
using scenario_detail::location_of;
using scenario_detail::Range;
using scenario_detail::TableReader;
using scenario_detail::kDeg;
using scenario_detail::material_index;

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

void parse_materials(const TableReader& root, ScenarioCommon& s) {
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

void parse_solver(const TableReader& root, ScenarioCommon& s) {
  // [solver] may be left out when [[stage]] tables give the end time.
  static const toml::table empty;
  const TableReader t = root.table("solver", !root.has("stage"))
                            .value_or(TableReader(empty, "solver", s.source));
  t.allow_only({"interpolation", "quadrature_points", "scheme", "end_time", "time_step", "cfl",
                "pic_fraction", "velocity_transfer", "xpic_order"});
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
  scenario_detail::parse_velocity_transfer(t, s);
}

void parse_initial_stress(const TableReader& root, ScenarioCommon& s) {
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

MaterialOverride parse_override(const TableReader& t, const ScenarioCommon& s) {
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

void parse_stages(const TableReader& root, ScenarioCommon& s) {
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

void parse_output(const TableReader& root, ScenarioCommon& s) {
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

// 3 when [grid] size is an array of three elements, else 2 (and the 2D parser reports any
// problem with the grid exactly as before 3D existed).
int dimension_of(const toml::table& doc) {
  const toml::table* grid = doc.get_as<toml::table>("grid");
  const toml::array* size = grid ? grid->get_as<toml::array>("size") : nullptr;
  return size && size->size() == 3 ? 3 : 2;
}

template <int D> ScenarioOf<D> parse_document(const toml::table& doc, const std::string& source) {
  const TableReader root(doc, "", source);
  root.allow_only({"title", "grid", "material", "body", "initial_stress", "gravity", "boundary",
                   "solver", "stage", "output"});
  ScenarioOf<D> s;
  s.source = source;
  s.title = root.string("title", std::string());
  scenario_detail::parse_grid<D>(root, s);
  parse_materials(root, s);
  scenario_detail::parse_bodies<D>(root, s);
  scenario_detail::parse_gravity<D>(root, s);
  scenario_detail::parse_boundary<D>(root, s);
  parse_initial_stress(root, s);
  parse_solver(root, s);
  parse_stages(root, s);
  parse_output(root, s);
  return s;
}

AnyScenario parse_any_document(const toml::table& doc, const std::string& source) {
  if (dimension_of(doc) == 3) return parse_document<3>(doc, source);
  return parse_document<2>(doc, source);
}

Scenario as_2d(AnyScenario any) {
  if (auto* s = std::get_if<Scenario>(&any)) return std::move(*s);
  const Scenario3& s = std::get<Scenario3>(any);
  throw ScenarioError(fmt::format("{}: key 'grid.size': this is a 3D scenario ([grid] size has 3 "
                                  "components); this command takes 2D scenarios only", s.source));
}

}  // namespace

Scenario parse_scenario(const std::string& text, const std::string& source) {
  return as_2d(parse_any_scenario(text, source));
}

Scenario parse_scenario(const std::string& text, const std::string& source,
                        const std::vector<std::pair<std::string, double>>& overrides) {
  return as_2d(parse_any_scenario(text, source, overrides));
}

AnyScenario parse_any_scenario(const std::string& text, const std::string& source,
                               const std::vector<std::pair<std::string, double>>& overrides) {
  toml::table doc = parse_toml(text, source);
  for (const auto& [key, value] : overrides) scenario_detail::set_key(doc, key, value, source);
  return parse_any_document(doc, source);
}

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

AnyScenario load_any_scenario(const std::string& path) {
  return parse_any_scenario(read_scenario_text(path), path);
}

}  // namespace skred
