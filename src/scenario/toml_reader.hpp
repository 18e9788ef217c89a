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
#include "scenario/schema.hpp"

namespace skred::scenario_detail {

struct Location {
  int line = 0;
  int column = 0;
};

Location location_of(const toml::source_region& r, Location fallback);

// The one place where scenario error messages are formatted.
[[noreturn]] void fail(const std::string& source, Location at, const std::string& key,
                       const std::string& message);

// An allowed interval for a number (declared in the schema).
using Range = schema::Range;

// Human name of a node's type, for "expected X, got Y" messages.
const char* type_name(const toml::node& n);

// A string value from a fixed list of spellings, each mapped to an enum value.
template <class E>
using Choices = std::initializer_list<std::pair<const char*, E>>;

class TableReader {
 public:
  // `path` is the dotted key path of this table ("" for the document root, "grid",
  // "material[0]", "boundary.x_min"); `fallback` is used when the table has no source. The
  // table follows the schema section named like its path without indices ("material[0]" ->
  // "material", "stage[1].material[0]" -> "stage.material"), if there is one.
  TableReader(const toml::table& table, std::string path, const std::string& source,
              Location fallback = {1, 1});

  // The same table read against another schema section (a body's shape, a boundary side).
  TableReader follows(std::string_view section) const;
  const schema::Section* section() const { return section_; }

  const toml::table& table() const { return table_; }
  const std::string& source() const { return source_; }
  Location where() const { return where_; }

  // Full key path of a member, e.g. key("size") == "grid.size".
  std::string key(std::string_view name) const;

  // Rejects every key not in `allowed`, reporting the first one in file order.
  void allow_only(std::initializer_list<std::string_view> allowed) const;
  void allow_only(const std::vector<std::string_view>& allowed) const;
  // Rejects every key its schema section (and `also`, e.g. a body's shape) does not declare.
  void allow_declared(const schema::Section* also = nullptr) const;

  const toml::node* find(std::string_view name) const { return table_.get(name); }
  bool has(std::string_view name) const { return find(name) != nullptr; }
  Location where(std::string_view name) const;  // the member's position, else the table's

  [[noreturn]] void fail_at(std::string_view name, const std::string& message) const;
  [[noreturn]] void fail_missing(std::string_view name) const;
  [[noreturn]] void fail_type(std::string_view name, const char* expected) const;

  // Typed getters reading the key's range and default from the schema: a key the schema
  // marks required must be present; one with a default value gets it; for one whose default
  // is derived from other keys (or "none") the caller passes the default (`*_or`). Numbers
  // must be finite; integers are accepted where a float is expected, not the other way round.
  double number(std::string_view name) const;
  double number_or(std::string_view name, double def) const;
  std::int64_t integer(std::string_view name) const;
  template <int D>
  Vec<D> vec(std::string_view name) const;
  template <int D>
  Vec<D> vec_or(std::string_view name, const Vec<D>& def) const;
  bool boolean_or(std::string_view name, bool def) const;
  // The key as declared in this table's schema section (std::logic_error if undeclared).
  const schema::Key& spec(std::string_view name) const;

  // Getters with the range given here, for checks that depend on other keys.
  double number(std::string_view name, Range range, std::optional<double> def = {}) const;
  std::int64_t integer(std::string_view name, std::int64_t lo, std::int64_t hi,
                       std::optional<std::int64_t> def = {}) const;
  std::string string(std::string_view name, std::optional<std::string> def = {}) const;
  // An array of exactly two numbers.
  Vec<2> vec2(std::string_view name, std::optional<Vec<2>> def = {}) const;
  // An array of exactly three numbers (3D scenarios).
  Vec<3> vec3(std::string_view name, std::optional<Vec<3>> def = {}) const;
  // A sub-table (standard or inline); nullopt when absent and not required.
  std::optional<TableReader> table(std::string_view name, bool required) const;
  // An array whose elements must all be tables ([[name]]); empty when absent.
  std::vector<TableReader> array_of_tables(std::string_view name) const;

  // A choice: the spelling must be one the schema declares (the message lists them); it maps
  // to the enum value of `choices`. Without `def` the key is required.
  template <class E>
  E choice(std::string_view name, Choices<E> choices, std::optional<E> def = {}) const {
    if (!has(name) && def) return *def;
    const std::string s = string(name);
    check_choice(name, s);
    for (const auto& [spelling, value] : choices)
      if (s == spelling) return value;
    fail_at(name, unknown_choice_message(s, names_of(choices)));
  }
  // Fails unless `value` is a spelling the schema declares for `name` (when declared there).
  void check_choice(std::string_view name, const std::string& value) const;

  template <class E>
  static std::vector<std::string> names_of(Choices<E> choices) {
    std::vector<std::string> names;
    for (const auto& c : choices) names.emplace_back(c.first);
    return names;
  }
  static std::string unknown_choice_message(const std::string& got, const std::vector<std::string>& allowed);

 private:
  const toml::table& table_;
  std::string path_;
  const std::string& source_;
  Location where_;
  const schema::Section* section_ = nullptr;
};

// Reads a number from an arbitrary node (array element etc.); `key` names it in messages.
double node_number(const toml::node& n, const std::string& source, const std::string& key, Location fallback);
// Reads an array of exactly two finite numbers from an arbitrary node.
Vec<2> node_vec2(const toml::node& n, const std::string& source, const std::string& key, Location fallback);
// Reads an array of exactly three finite numbers (a 3D scenario's vectors).
Vec<3> node_vec3(const toml::node& n, const std::string& source, const std::string& key, Location fallback);

}  // namespace skred::scenario_detail
