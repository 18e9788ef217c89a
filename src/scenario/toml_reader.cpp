#include "scenario/toml_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace skred::scenario_detail {

Location location_of(const toml::source_region& r, Location fallback) {
  if (r.begin.line == 0) return fallback;
  return {static_cast<int>(r.begin.line), static_cast<int>(r.begin.column)};
}

void fail(const std::string& source, Location at, const std::string& key, const std::string& message) {
  throw ScenarioError(fmt::format("{}:{}:{}: key '{}': {}", source, at.line, at.column, key, message));
}

const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    case toml::node_type::none: break;
  }
  return "nothing";
}

double node_number(const toml::node& n, const std::string& source, const std::string& key,
                   Location fallback) {
  const Location at = location_of(n.source(), fallback);
  double v = 0.0;
  if (const auto* i = n.as_integer()) {
    v = static_cast<double>(i->get());
  } else if (const auto* f = n.as_floating_point()) {
    v = f->get();
  } else {
    fail(source, at, key, fmt::format("expected a number, got {}", type_name(n)));
  }
  if (!std::isfinite(v)) fail(source, at, key, fmt::format("must be finite, got {}", v));
  return v;
}

Vec<2> node_vec2(const toml::node& n, const std::string& source, const std::string& key, Location fallback) {
  const Location at = location_of(n.source(), fallback);
  const auto* arr = n.as_array();
  if (!arr) fail(source, at, key, fmt::format("expected an array of 2 numbers, got {}", type_name(n)));
  if (arr->size() != 2)
    fail(source, at, key, fmt::format("expected an array of 2 numbers, got {} elements", arr->size()));
  Vec<2> v;
  for (int d = 0; d < 2; ++d) v[d] = node_number(*arr->get(d), source, key, at);
  return v;
}

Vec<3> node_vec3(const toml::node& n, const std::string& source, const std::string& key, Location fallback) {
  const Location at = location_of(n.source(), fallback);
  const auto* arr = n.as_array();
  if (!arr)
    fail(source, at, key,
         fmt::format("expected an array of 3 numbers [x, y, z] (the grid is 3D), "
                     "got {}",
                     type_name(n)));
  if (arr->size() != 3)
    fail(source, at, key,
         fmt::format("expected an array of 3 numbers [x, y, z] (the grid is 3D), "
                     "got {} elements",
                     arr->size()));
  Vec<3> v;
  for (int d = 0; d < 3; ++d) v[d] = node_number(*arr->get(d), source, key, at);
  return v;
}

namespace {

// "stage[1].material[0]" -> "stage.material": the schema section a table path follows.
std::string section_name(const std::string& path) {
  std::string out;
  bool in_index = false;
  for (char c : path) {
    if (c == '[')
      in_index = true;
    else if (c == ']')
      in_index = false;
    else if (!in_index)
      out += c;
  }
  return out;
}

const schema::Section* find_section(const std::string& name) {
  for (const schema::Section& s : schema::sections())
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace

TableReader::TableReader(const toml::table& table, std::string path, const std::string& source,
                         Location fallback)
    : table_(table),
      path_(std::move(path)),
      source_(source),
      where_(location_of(table.source(), fallback)),
      section_(find_section(section_name(path_))) {}

TableReader TableReader::follows(std::string_view section) const {
  TableReader t = *this;
  t.section_ = &schema::section(section);
  return t;
}

const schema::Key& TableReader::spec(std::string_view name) const {
  if (!section_)
    throw std::logic_error("table '" + path_ + "' follows no schema section (key '" + std::string(name) +
                           "')");
  return section_->at(name);
}

void TableReader::allow_declared(const schema::Section* also) const {
  std::vector<std::string_view> keys;
  for (const auto* s : {section_, also})
    if (s)
      for (const schema::Key& k : s->keys) keys.push_back(k.name);
  allow_only(keys);
}

double TableReader::number(std::string_view name) const {
  const schema::Key& k = spec(name);
  if (!has(name) && k.def.kind == schema::DefaultKind::Value) return k.def.value;
  return number(name, k.range);
}

double TableReader::number_or(std::string_view name, double def) const {
  return number(name, spec(name).range, def);
}

std::int64_t TableReader::integer(std::string_view name) const {
  const schema::Key& k = spec(name);
  std::optional<std::int64_t> def;
  if (k.def.kind == schema::DefaultKind::Value) def = static_cast<std::int64_t>(k.def.value);
  return integer(name, static_cast<std::int64_t>(k.range.lo), static_cast<std::int64_t>(k.range.hi), def);
}

template <int D>
Vec<D> TableReader::vec(std::string_view name) const {
  Vec<D> v;
  if constexpr (D == 2)
    v = vec2(name);
  else
    v = vec3(name);
  const Range r = spec(name).range;
  for (int d = 0; d < D; ++d)
    if (!r.contains(v[d]))
      fail_at(name, fmt::format("component {} must be {}, got {}", "xyz"[d], r.describe(), v[d]));
  return v;
}

template <int D>
Vec<D> TableReader::vec_or(std::string_view name, const Vec<D>& def) const {
  return has(name) ? vec<D>(name) : def;
}

template Vec<2> TableReader::vec<2>(std::string_view) const;
template Vec<3> TableReader::vec<3>(std::string_view) const;
template Vec<2> TableReader::vec_or<2>(std::string_view, const Vec<2>&) const;
template Vec<3> TableReader::vec_or<3>(std::string_view, const Vec<3>&) const;

bool TableReader::boolean_or(std::string_view name, bool def) const {
  spec(name);
  if (!has(name)) return def;
  const auto v = find(name)->value<bool>();
  if (!v || !find(name)->is_boolean()) fail_type(name, "a boolean (true or false)");
  return *v;
}

void TableReader::check_choice(std::string_view name, const std::string& value) const {
  const schema::Key* k = section_ ? section_->find(name) : nullptr;
  if (!k || !*k->choices) return;
  const auto allowed = schema::choices_of(*k);
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end())
    fail_at(name, unknown_choice_message(value, allowed));
}

std::string TableReader::key(std::string_view name) const {
  if (path_.empty()) return std::string(name);
  return fmt::format("{}.{}", path_, name);
}

Location TableReader::where(std::string_view name) const {
  if (const auto* n = find(name)) return location_of(n->source(), where_);
  return where_;
}

void TableReader::allow_only(std::initializer_list<std::string_view> allowed) const {
  allow_only(std::vector<std::string_view>(allowed));
}

void TableReader::allow_only(const std::vector<std::string_view>& allowed) const {
  const toml::key* first = nullptr;
  Location first_at{};
  for (const auto& [k, node] : table_) {
    if (std::find(allowed.begin(), allowed.end(), k.str()) != allowed.end()) continue;
    const Location at = location_of(k.source(), location_of(node.source(), where_));
    if (!first || at.line < first_at.line || (at.line == first_at.line && at.column < first_at.column)) {
      first = &k;
      first_at = at;
    }
  }
  if (!first) return;
  std::string list;
  for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
  fail(source_, first_at, key(first->str()), fmt::format("unknown key; allowed keys here: {}", list));
}

void TableReader::fail_at(std::string_view name, const std::string& message) const {
  fail(source_, where(name), key(name), message);
}

void TableReader::fail_missing(std::string_view name) const {
  fail(source_, where_, key(name), "required key is missing");
}

void TableReader::fail_type(std::string_view name, const char* expected) const {
  fail_at(name, fmt::format("expected {}, got {}", expected, type_name(*find(name))));
}

double TableReader::number(std::string_view name, Range range, std::optional<double> def) const {
  const auto* n = find(name);
  if (!n) {
    if (def) return *def;
    fail_missing(name);
  }
  if (!n->is_number()) fail_type(name, "a number");
  const double v = node_number(*n, source_, key(name), where_);
  if (!range.contains(v)) fail_at(name, fmt::format("must be {}, got {}", range.describe(), v));
  return v;
}

std::int64_t TableReader::integer(std::string_view name, std::int64_t lo, std::int64_t hi,
                                  std::optional<std::int64_t> def) const {
  const auto* n = find(name);
  if (!n) {
    if (def) return *def;
    fail_missing(name);
  }
  const auto* i = n->as_integer();
  if (!i) fail_type(name, "an integer");
  const std::int64_t v = i->get();
  if (v < lo || v > hi) fail_at(name, fmt::format("must be an integer from {} to {}, got {}", lo, hi, v));
  return v;
}

std::string TableReader::string(std::string_view name, std::optional<std::string> def) const {
  const auto* n = find(name);
  if (!n) {
    if (def) return *def;
    fail_missing(name);
  }
  const auto* s = n->as_string();
  if (!s) fail_type(name, "a string");
  return s->get();
}

Vec<2> TableReader::vec2(std::string_view name, std::optional<Vec<2>> def) const {
  const auto* n = find(name);
  if (!n) {
    if (def) return *def;
    fail_missing(name);
  }
  return node_vec2(*n, source_, key(name), where_);
}

Vec<3> TableReader::vec3(std::string_view name, std::optional<Vec<3>> def) const {
  const auto* n = find(name);
  if (!n) {
    if (def) return *def;
    fail_missing(name);
  }
  return node_vec3(*n, source_, key(name), where_);
}

std::optional<TableReader> TableReader::table(std::string_view name, bool required) const {
  const auto* n = find(name);
  if (!n) {
    if (required) fail_missing(name);
    return std::nullopt;
  }
  const auto* t = n->as_table();
  if (!t) fail_type(name, fmt::format("a table ([{}])", key(name)).c_str());
  return TableReader(*t, key(name), source_, where(name));
}

std::vector<TableReader> TableReader::array_of_tables(std::string_view name) const {
  std::vector<TableReader> out;
  const auto* n = find(name);
  if (!n) return out;
  const auto* arr = n->as_array();
  if (!arr) fail_type(name, fmt::format("an array of tables ([[{}]])", key(name)).c_str());
  const Location arr_at = where(name);
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const auto& el = *arr->get(i);
    const std::string k = fmt::format("{}[{}]", key(name), i);
    const auto* t = el.as_table();
    if (!t)
      fail(source_, location_of(el.source(), arr_at), k,
           fmt::format("expected a table ([[{}]]), got {}", key(name), type_name(el)));
    out.emplace_back(*t, k, source_, location_of(el.source(), arr_at));
  }
  return out;
}

std::string TableReader::unknown_choice_message(const std::string& got,
                                                const std::vector<std::string>& allowed) {
  std::string list;
  for (const auto& a : allowed) list += fmt::format("{}\"{}\"", list.empty() ? "" : ", ", a);
  return fmt::format("unknown value \"{}\"; allowed values: {}", got, list);
}

}  // namespace skred::scenario_detail
