// Scenario file parser: TOML text -> validated Scenario. The schema is documented in
// docs/scenario.md; keep the two in step.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "scenario/build.hpp"
#include "scenario/estimate.hpp"
#include "scenario/parse_transfer.hpp"
#include "scenario/parser_detail.hpp"
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

const char* to_string(Stage::RestMeasure r) {
  switch (r) {
    case Stage::RestMeasure::Auto: return "auto";
    case Stage::RestMeasure::Points: return "points";
    case Stage::RestMeasure::Material: return "material";
    case Stage::RestMeasure::Displacement: return "displacement";
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
using scenario_detail::kDeg;
using scenario_detail::Location;
using scenario_detail::location_of;
using scenario_detail::material_index;
using scenario_detail::Range;
using scenario_detail::TableReader;

// The strength keys of the model (Thesis eq. 5.1-5.4; Paper III §C.3.2; Acosta §3.2), read
// against the model's declared parameters (src/material/<model>/info.hpp).
void parse_strength(const TableReader& t, Material& m) {
  const std::string model_section = fmt::format("material ({})", to_string(m.model));
  const TableReader p = m.model == Model::LinearElastic ? t : t.follows(model_section);
  t.allow_declared(m.model == Model::LinearElastic ? nullptr : &schema::section(model_section));
  switch (m.model) {
    case Model::LinearElastic: return;
    case Model::MohrCoulomb: {
      MohrCoulombParams& mc = m.mohr_coulomb;
      const double phi_deg = p.number("friction");
      mc.friction = phi_deg * kDeg;
      mc.cohesion = p.number("cohesion");
      if (mc.friction == 0.0 && mc.cohesion == 0.0)
        t.fail_at("cohesion", "a Mohr-Coulomb material needs friction > 0 or cohesion > 0");
      if (p.number("dilation") > phi_deg)
        p.fail_at("dilation", fmt::format("the dilation angle must not exceed the friction angle "
                                          "{} deg",
                                          phi_deg));
      mc.dilation = p.number("dilation") * kDeg;
      if (t.has("tension_cutoff")) mc.tension_cutoff = p.number("tension_cutoff");
      if (t.has("initial_void_ratio") != t.has("max_void_ratio"))
        t.fail_at(t.has("max_void_ratio") ? "max_void_ratio" : "initial_void_ratio",
                  "the dilation cut-off needs both initial_void_ratio and max_void_ratio");
      if (t.has("max_void_ratio")) {
        mc.initial_void_ratio = p.number("initial_void_ratio");
        mc.max_void_ratio = p.number("max_void_ratio");
        if (!(mc.max_void_ratio > mc.initial_void_ratio))
          t.fail_at("max_void_ratio", fmt::format("must be > initial_void_ratio {}, got {}",
                                                  mc.initial_void_ratio, mc.max_void_ratio));
      }
      return;
    }
    case Model::Tresca: m.mohr_coulomb.cohesion = p.number("cohesion"); return;
    case Model::VonMises: {
      VonMisesParams& vm = m.von_mises;
      vm.cohesion_peak = p.number("cohesion");
      vm.cohesion_residual = p.number_or("residual_cohesion", vm.cohesion_peak);
      if (vm.cohesion_residual > vm.cohesion_peak)
        t.fail_at("residual_cohesion",
                  fmt::format("must be <= cohesion {}, got {}", vm.cohesion_peak, vm.cohesion_residual));
      vm.softening_modulus = p.number("softening_modulus");
      return;
    }
  }
}

void parse_materials(const TableReader& root, ScenarioCommon& s) {
  const auto tables = root.array_of_tables("material");
  if (tables.empty())
    fail(s.source, root.where("material"), "material", "at least one [[material]] table is required");
  std::map<std::string, Location> seen;
  for (const auto& t : tables) {
    Material m;
    m.name = t.string("name");
    if (m.name.empty()) t.fail_at("name", "must not be empty");
    if (const auto it = seen.find(m.name); it != seen.end())
      t.fail_at("name", fmt::format("duplicate material name \"{}\" (first defined on line {})", m.name,
                                    it->second.line));
    seen.emplace(m.name, t.where("name"));
    const auto M = [](Model x) { return std::pair{to_string(x), x}; };
    m.model = t.choice<Model>(
        "model", {M(Model::LinearElastic), M(Model::MohrCoulomb), M(Model::Tresca), M(Model::VonMises)});
    parse_strength(t, m);
    m.density = t.number("density");
    m.elastic.young = t.number("young");
    m.elastic.poisson = t.number("poisson");
    s.materials.push_back(std::move(m));
  }
}

// `slide`: a deformable body's material can yield (what solver.velocity_transfer = "auto" and
// volumetric_strain = "auto" decide by).
void parse_solver(const TableReader& root, ScenarioCommon& s, bool slide) {
  // [solver] may be left out when [[stage]] tables give the end time.
  static const toml::table empty;
  const TableReader t =
      root.table("solver", !root.has("stage")).value_or(TableReader(empty, "solver", s.source));
  t.allow_declared();
  const auto I = [](Interpolation i) { return std::pair{to_string(i), i}; };
  s.interpolation = t.choice<Interpolation>("interpolation",
                                            {I(Interpolation::Linear), I(Interpolation::Gimp),
                                             I(Interpolation::GimpQuadrature), I(Interpolation::Bspline)},
                                            Interpolation::Gimp);
  s.quadrature_points = static_cast<int>(t.integer("quadrature_points"));
  const auto S = [](StressScheme x) { return std::pair{to_string(x), x}; };
  s.scheme = t.choice<StressScheme>("scheme",
                                    {S(StressScheme::USF), S(StressScheme::USL), S(StressScheme::Averaged)},
                                    StressScheme::Averaged);
  // With [[stage]] tables the stage durations give the end time (parse_stages).
  if (root.has("stage")) {
    if (t.has("end_time"))
      t.fail_at("end_time", "the [[stage]] durations set the end time; remove solver.end_time");
  } else {
    s.end_time = t.number("end_time");
  }
  s.time_step = t.number_or("time_step", 0.0);
  s.cfl = t.number("cfl");
  s.allow_unstable_time_step = t.boolean_or("allow_unstable_time_step", false);
  if (s.allow_unstable_time_step && !t.has("time_step"))
    t.fail_at("allow_unstable_time_step", "only meaningful with a fixed solver.time_step");
  s.pic_fraction = t.number("pic_fraction");
  scenario_detail::parse_velocity_transfer(t, s, slide);
  scenario_detail::parse_integrator(root, t, s);
}

void parse_initial_stress(const TableReader& root, ScenarioCommon& s) {
  const auto t = root.table("initial_stress", false);
  if (!t) return;
  t->allow_declared();
  InitialStress& is = s.initial_stress;
  const toml::node* n = t->find("k0");
  if (!n) t->fail_missing("k0");
  if (n->is_number()) {
    is.rule = K0Rule::Value;
    is.k0 = t->number("k0");
    return;
  }
  if (!n->is_string()) t->fail_type("k0", "\"poisson\", \"jaky\" or a number");
  is.rule = t->choice<K0Rule>("k0", {{"poisson", K0Rule::Poisson}, {"jaky", K0Rule::Jaky}});
}

MaterialOverride parse_override(const TableReader& t, const ScenarioCommon& s, double duration) {
  t.allow_declared();
  MaterialOverride o;
  o.material = material_index(t, "name", s);
  const Material& m = s.materials[static_cast<std::size_t>(o.material)];
  const bool mc = m.model == Model::MohrCoulomb;
  if (!mc && (t.has("friction") || t.has("dilation")))
    t.fail_at(t.has("friction") ? "friction" : "dilation",
              fmt::format("material \"{}\" is {}; only mohr-coulomb has a friction or dilation "
                          "angle",
                          m.name, to_string(m.model)));
  if (!m.plastic() && t.has("cohesion"))
    t.fail_at("cohesion", fmt::format("material \"{}\" is linear-elastic and has no cohesion", m.name));
  if (t.has("friction")) o.friction = t.number("friction") * kDeg;
  if (t.has("cohesion")) {
    o.cohesion = t.number("cohesion");
    if (!mc && *o.cohesion == 0.0)
      t.fail_at("cohesion", fmt::format("must be > 0 for {}, got 0", to_string(m.model)));
  }
  if (t.has("dilation")) o.dilation = t.number("dilation") * kDeg;
  if (t.has("density")) o.density = t.number("density");
  if (t.has("density_ramp_time") && !o.density)
    t.fail_at("density_ramp_time", "only allowed together with density");
  o.density_ramp_time = t.number("density_ramp_time");
  if (o.density_ramp_time > duration)
    t.fail_at("density_ramp_time",
              fmt::format("the ramp ({} s) is longer than the stage ({} s)", o.density_ramp_time, duration));
  const double phi = o.friction.value_or(m.mohr_coulomb.friction);
  if (o.dilation.value_or(m.mohr_coulomb.dilation) > phi + 1e-12)
    t.fail_at(o.dilation ? "dilation" : "friction", "the dilation angle must not exceed the friction angle");
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
    st.integrator = s.integrator;
    st.implicit = s.implicit;
    s.stages.push_back(st);
    return;
  }
  if (s.gravity_ramp_time > 0)
    fail(s.source, root.table("gravity", true)->where("ramp_time"), "gravity.ramp_time",
         "with [[stage]] tables give the ramp per stage (stage.gravity_ramp_time)");
  s.end_time = 0.0;
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const TableReader& t = tables[i];
    t.allow_declared();
    Stage st;
    st.name = t.string("name", fmt::format("stage-{}", i));
    st.duration = t.number("duration");
    st.gravity_ramp_time = t.number("gravity_ramp_time");
    if (st.gravity_ramp_time > st.duration)
      t.fail_at("gravity_ramp_time", fmt::format("the ramp ({} s) is longer than the stage ({} s)",
                                                 st.gravity_ramp_time, st.duration));
    st.elastic = t.boolean_or("elastic", false);
    st.strength_reduction = t.number("strength_reduction");
    for (const auto& m : t.array_of_tables("material"))
      st.overrides.push_back(parse_override(m, s, st.duration));
    st.rest_speed = t.number("rest_speed");
    if (t.has("rest_time") && st.rest_speed == 0.0)
      t.fail_at("rest_time", "only allowed together with rest_speed > 0");
    st.rest_time = t.number_or("rest_time", 0.0);
    if (st.rest_speed > 0.0 && !t.has("rest_time")) t.fail_missing("rest_time");
    st.rest_measure = t.choice<Stage::RestMeasure>("rest_measure",
                                                   {{"auto", Stage::RestMeasure::Auto},
                                                    {"points", Stage::RestMeasure::Points},
                                                    {"material", Stage::RestMeasure::Material},
                                                    {"displacement", Stage::RestMeasure::Displacement}},
                                                   Stage::RestMeasure::Auto);
    st.local_damping = t.number("local_damping");
    st.runout_thickness = t.number_or("runout_thickness", 0.0);
    st.integrator = t.choice<IntegratorKind>(
        "integrator", {{"explicit", IntegratorKind::Explicit}, {"implicit", IntegratorKind::Implicit}},
        s.integrator);
    st.implicit = s.implicit;  // with the stage's [stage.implicit] over it
    if (const auto im = t.table("implicit", false))
      scenario_detail::parse_implicit_settings(im->follows("implicit"), st.implicit);
    s.end_time += st.duration;
    s.stages.push_back(std::move(st));
  }
  if (s.end_time > schema::section("stage").at("duration").range.hi)
    fail(s.source, tables.back().where("duration"), tables.back().key("duration"),
         fmt::format("the stages add up to {} s; at most {} s are allowed", s.end_time,
                     schema::section("stage").at("duration").range.hi));
}

// Frames and series rows a run may write at most: more is a typo, not an analysis.
constexpr double kMaxFrames = 1e5;
constexpr double kMaxSeriesRows = 1e7;

// output.fields: "default", "all", or a list of field names and "default"; the names in the
// order of output_fields::all(), each once.
// `table` is the [output] table, if there is one.
std::vector<std::string> parse_output_fields(const std::optional<TableReader>& table) {
  const std::vector<std::string>& all = output_fields::all();
  std::vector<std::string> given;
  if (!table || !table->has("fields")) {
    given.push_back("default");
  } else if (table->find("fields")->is_string()) {
    given.push_back(table->string("fields"));
  } else {
    const TableReader& o = *table;
    const auto* arr = o.find("fields")->as_array();
    if (!arr || arr->empty())
      o.fail_type("fields", "\"default\", \"all\" or a non-empty list of field names");
    for (const auto& n : *arr) {
      if (!n.is_string()) o.fail_type("fields", "a list of field names (strings)");
      given.push_back(*n.value<std::string>());
    }
  }
  std::set<std::string> chosen;
  for (const std::string& g : given) {
    if (g == "all" || g == "default") {
      const auto& set = g == "all" ? all : output_fields::defaults();
      chosen.insert(set.begin(), set.end());
    } else if (std::find(all.begin(), all.end(), g) != all.end()) {
      chosen.insert(g);
    } else {
      std::vector<std::string> allowed = {"default", "all"};
      allowed.insert(allowed.end(), all.begin(), all.end());
      table->fail_at("fields", TableReader::unknown_choice_message(g, allowed));  // only given names fail
    }
  }
  std::vector<std::string> names;
  for (const std::string& n : all)
    if (chosen.count(n)) names.push_back(n);
  return names;
}

void parse_output(const TableReader& root, ScenarioCommon& s, int dimensions) {
  const auto o = root.table("output", false);
  // The hazard maps lie over a 3D run's horizontal plane; a 2D run has none to write.
  if (o && dimensions == 2)
    for (const char* key : {"maps", "map_threshold"})
      if (o->has(key))
        o->fail_at(key,
                   "3D only: the hazard maps lie over a 3D run's x-z plane; a 2D run writes none "
                   "(its runout is in summary.json and series.csv)");
  s.output_interval = s.end_time / 20.0;
  if (o) {
    o->allow_declared();
    s.output_interval = o->number_or("interval", s.output_interval);
    if (s.end_time / s.output_interval > kMaxFrames)
      o->fail_at("interval", fmt::format("gives {:.3g} particle frames over {} s; at most {:.0f} are "
                                         "allowed",
                                         s.end_time / s.output_interval, s.end_time, kMaxFrames));
  }
  s.series_interval = s.output_interval / 10.0;
  if (o) {
    s.series_interval = o->number_or("series_interval", s.series_interval);
    if (s.end_time / s.series_interval > kMaxSeriesRows)
      o->fail_at("series_interval", fmt::format("gives {:.3g} rows of series.csv over {} s; at most "
                                                "{:.0f} are allowed",
                                                s.end_time / s.series_interval, s.end_time, kMaxSeriesRows));
    s.output_compression = o->boolean_or("compression", true);
    s.output_maps = o->boolean_or("maps", true);
    s.map_threshold = o->number_or("map_threshold", 0.0);
  }
  s.output_fields = parse_output_fields(o);
}

}  // namespace

namespace {

// Parts a dotted key may have. toml++ builds a dotted key's tables recursively, so a key of
// a million parts would overflow the stack; no scenario key has more than a few.
constexpr int kMaxKeyParts = 64;

// Refuses a dotted key (or table header) of more than kMaxKeyParts parts before toml++ sees
// it. Dots are counted in runs of key characters; strings and comments are skipped, and
// any other character ('=', ',', '[', a newline) ends the run, so float values never add up.
void check_key_depth(std::string_view text, const std::string& source) {
  int line = 1, column = 0, dots = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    ++column;
    if (c == '\n') {
      ++line, column = 0, dots = 0;
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      const bool triple = text.substr(i, 3) == std::string(3, c);
      const std::string_view end = triple ? text.substr(i, 3) : text.substr(i, 1);
      std::size_t j = i + end.size();
      while (j < text.size() && text.substr(j, end.size()) != end) {
        if (c == '"' && text[j] == '\\') ++j;  // an escaped character
        if (j < text.size() && text[j] == '\n') ++line, column = 0;
        if (!triple && j < text.size() && text[j] == '\n') break;  // left to toml++ to report
        ++j;
      }
      column += static_cast<int>(j - i);
      i = std::min(text.size(), j + end.size()) - 1;
    } else if (c == '.') {
      if (++dots >= kMaxKeyParts)
        throw ScenarioError(
            fmt::format("{}:{}:{}: syntax error: a dotted key with more than {} "
                        "parts",
                        source, line, column, kMaxKeyParts));
    } else if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == ' ' ||
                 c == '\t' || c == '+')) {
      dots = 0;
    }
  }
}

toml::table parse_toml(const std::string& text, const std::string& source) {
  check_key_depth(text, source);
  try {
    return toml::parse(std::string_view(text), std::string_view(source));
  } catch (const toml::parse_error& e) {
    const Location at = location_of(e.source(), Location{1, 1});
    throw ScenarioError(
        fmt::format("{}:{}:{}: syntax error: {}", source, at.line, at.column, e.description()));
  }
}

// 3 when [grid] size is an array of three elements, else 2 (and the 2D parser reports any
// problem with the grid exactly as before 3D existed).
int dimension_of(const toml::table& doc) {
  const toml::table* grid = doc.get_as<toml::table>("grid");
  const toml::array* size = grid ? grid->get_as<toml::array>("size") : nullptr;
  return size && size->size() == 3 ? 3 : 2;
}

// [splitting] and the bodies' `split` keys (Thesis §3.4).
template <int D>
void parse_splitting(const TableReader& root, ScenarioOf<D>& s) {
  bool any = false;
  for (const auto& b : s.bodies) any = any || b.split;
  const auto t = root.table("splitting", false);
  if (t && !any) t->fail_at("alpha", "no body has split = true");
  if (!any) return;
  static const toml::table empty;
  const TableReader r = t.value_or(TableReader(empty, "splitting", s.source));
  r.allow_declared();
  SplitSettings& sp = s.splitting;
  sp.alpha = r.number("alpha");
  sp.beta = r.number("beta");
  sp.gamma = r.number("gamma");
  sp.reference_after = static_cast<int>(r.integer("reference_after"));
  sp.min_volume = std::pow(r.number("min_size") * s.cell_size, D);
  sp.rebalance_above = r.number("rebalance_above");
  double points = 0;
  for (const auto& b : s.bodies) points += static_cast<double>(count_points(s, b));
  s.max_points_given = r.has("max_points");
  sp.max_points =
      s.max_points_given ? static_cast<long>(r.integer("max_points")) : static_cast<long>(10 * points);
  for (const auto& b : s.bodies) sp.body_splits.push_back(b.split ? 1 : 0);
}

template <int D>
ScenarioOf<D> parse_document(const toml::table& doc, const std::string& source) {
  const TableReader root(doc, "", source);
  root.allow_declared();
  ScenarioOf<D> s;
  s.source = source;
  s.title = root.string("title", std::string());
  scenario_detail::parse_grid<D>(root, s);
  parse_materials(root, s);
  if constexpr (D == 2)
    scenario_detail::parse_ground(root, s);
  else
    scenario_detail::parse_ground3(root, s);
  s.later_body_wins = root.choice<bool>("body_overlap", {{"error", false}, {"later-wins", true}}, false);
  scenario_detail::parse_bodies<D>(root, s);
  scenario_detail::check_overlaps<D>(root, s);
  parse_splitting(root, s);
  scenario_detail::parse_gravity<D>(root, s);
  scenario_detail::parse_boundary<D>(root, s);
  scenario_detail::parse_contacts<D>(root, s);
  scenario_detail::add_dilation_continua<D>(root, s);
  parse_initial_stress(root, s);
  parse_solver(root, s, std::ranges::any_of(s.bodies, [&](const BodyOf<D>& b) {
                 return !b.rigid && s.materials[static_cast<std::size_t>(b.material)].plastic();
               }));
  parse_stages(root, s);
  scenario_detail::check_integrators<D>(root, s);
  parse_output(root, s, D);
  scenario_detail::check_time_step<D>(root, s);
  return s;
}

AnyScenario parse_any_document(const toml::table& doc, const std::string& source) {
  if (dimension_of(doc) == 3) return parse_document<3>(doc, source);
  return parse_document<2>(doc, source);
}

Scenario as_2d(AnyScenario any) {
  if (auto* s = std::get_if<Scenario>(&any)) return std::move(*s);
  const Scenario3& s = std::get<Scenario3>(any);
  throw ScenarioError(
      fmt::format("{}: key 'grid.size': this is a 3D scenario ([grid] size has 3 "
                  "components); this command takes 2D scenarios only",
                  s.source));
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
                               const std::vector<std::pair<std::string, double>>& overrides,
                               const std::vector<std::pair<std::string, std::string>>& text_overrides) {
  toml::table doc = parse_toml(text, source);
  for (const auto& [key, value] : overrides) scenario_detail::set_key(doc, key, value, source);
  for (const auto& [key, value] : text_overrides) scenario_detail::set_key(doc, key, value, source);
  return parse_any_document(doc, source);
}

namespace scenario_detail {

std::string input_file_problem(const std::string& path, std::uintmax_t max_bytes) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) return "";  // opening it says why
  if (!std::filesystem::is_regular_file(status))
    return std::filesystem::is_directory(status) ? "it is a directory, not a file"
                                                 : "it is not a regular file (a device, pipe or socket)";
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > max_bytes)
    return fmt::format("it holds {} bytes, more than the {} MiB an input file of skred may have", size,
                       max_bytes >> 20);
  return "";
}

}  // namespace scenario_detail

std::string read_scenario_text(const std::string& path) {
  if (const std::string why = scenario_detail::input_file_problem(path, scenario_detail::kMaxScenarioBytes);
      !why.empty())
    throw ScenarioError(fmt::format("{}: cannot read as a scenario file: {}", path, why));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ScenarioError(fmt::format("{}: cannot open scenario file: {}", path, std::strerror(errno)));
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
