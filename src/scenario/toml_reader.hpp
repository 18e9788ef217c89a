// Typed, validating access to a toml++ table for the scenario parser. Every failure throws
// ScenarioError with the message "FILE:LINE:COLUMN: key 'path.key': message", located at
// the offending node (or at the enclosing table when a required key is missing).
// Internal to src/scenario; nothing outside the parser should include it.
#pragma once
#include <toml++/toml.h>

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "scenario/scenario.hpp"

namespace skred::scenario_detail {

struct Location {
  int line = 0;
  int column = 0;
};

Location location_of(const toml::source_region& r, Location fallback);

// The one place where scenario error messages are formatted.
[[noreturn]] void fail(const std::string& source, Location at, const std::string& key,
                       const std::string& message);

// An allowed interval for a number; open ends exclude the bound.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  bool contains(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string describe() const;  // e.g. "> 0", ">= 0 and < 0.5"

  static Range any() { return {}; }
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
};

// Human name of a node's type, for "expected X, got Y" messages.
const char* type_name(const toml::node& n);

// A string value from a fixed list of spellings, each mapped to an enum value.
template <class E> using Choices = std::initializer_list<std::pair<const char*, E>>;

class TableReader {
 public:
  // `path` is the dotted key path of this table ("" for the document root, "grid",
  // "material[0]", "boundary.x_min"); `fallback` is used when the table has no source.
  TableReader(const toml::table& table, std::string path, const std::string& source,
              Location fallback = {1, 1});

  const toml::table& table() const { return table_; }
  const std::string& source() const { return source_; }
  Location where() const { return where_; }

  // Full key path of a member, e.g. key("size") == "grid.size".
  std::string key(std::string_view name) const;

  // Rejects every key not in `allowed`, reporting the first one in file order.
  void allow_only(std::initializer_list<std::string_view> allowed) const;

  const toml::node* find(std::string_view name) const { return table_.get(name); }
  bool has(std::string_view name) const { return find(name) != nullptr; }
  Location where(std::string_view name) const;  // the member's position, else the table's

  [[noreturn]] void fail_at(std::string_view name, const std::string& message) const;
  [[noreturn]] void fail_missing(std::string_view name) const;
  [[noreturn]] void fail_type(std::string_view name, const char* expected) const;

  // Typed getters. Without a default the key is required. Numbers must be finite; integers
  // are accepted where a float is expected, but not the other way round.
  double number(std::string_view name, Range range, std::optional<double> def = {}) const;
  std::int64_t integer(std::string_view name, std::int64_t lo, std::int64_t hi,
                       std::optional<std::int64_t> def = {}) const;
  std::string string(std::string_view name, std::optional<std::string> def = {}) const;
  // An array of exactly two numbers.
  Vec<2> vec2(std::string_view name, std::optional<Vec<2>> def = {}) const;
  // An array of exactly three numbers (3D scenarios).
  Vec<3> vec3(std::string_view name, std::optional<Vec<3>> def = {}) const;
  // vec2 or vec3 by dimension.
  template <int D> Vec<D> vec(std::string_view name, std::optional<Vec<D>> def = {}) const {
    if constexpr (D == 2) return vec2(name, def);
    else return vec3(name, def);
  }
  // A sub-table (standard or inline); nullopt when absent and not required.
  std::optional<TableReader> table(std::string_view name, bool required) const;
  // An array whose elements must all be tables ([[name]]); empty when absent.
  std::vector<TableReader> array_of_tables(std::string_view name) const;

  template <class E>
  E choice(std::string_view name, Choices<E> choices, std::optional<E> def = {}) const {
    if (!has(name) && def) return *def;
    const std::string s = string(name);
    for (const auto& [spelling, value] : choices)
      if (s == spelling) return value;
    fail_at(name, unknown_choice_message(s, names_of(choices)));
  }

  template <class E> static std::vector<std::string> names_of(Choices<E> choices) {
    std::vector<std::string> names;
    for (const auto& c : choices) names.emplace_back(c.first);
    return names;
  }
  static std::string unknown_choice_message(const std::string& got,
                                            const std::vector<std::string>& allowed);

 private:
  const toml::table& table_;
  std::string path_;
  const std::string& source_;
  Location where_;
};

// Reads a number from an arbitrary node (array element etc.); `key` names it in messages.
double node_number(const toml::node& n, const std::string& source, const std::string& key,
                   Location fallback);
// Reads an array of exactly two finite numbers from an arbitrary node.
Vec<2> node_vec2(const toml::node& n, const std::string& source, const std::string& key,
                 Location fallback);
// Reads an array of exactly three finite numbers (a 3D scenario's vectors).
Vec<3> node_vec3(const toml::node& n, const std::string& source, const std::string& key,
                 Location fallback);

}  // namespace skred::scenario_detail
