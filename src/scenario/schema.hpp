// The scenario file's schema, declared once per section: every key with its type, unit,
// default, allowed range and meaning. The parser validates against it (TableReader reads a
// key's range, default and the section's allowed keys from here) and docs/scenario.md's key
// tables are generated from it (`skred schema --update docs/scenario.md`; a test fails when
// the file and the schema differ). Model-specific material keys come from each model's
// parameter table (src/material/<model>/info.hpp).
#pragma once
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace skred::schema {

// An allowed interval for a number (or each component of a vector); open ends exclude the
// bound.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  constexpr bool contains(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string describe() const;  // e.g. "> 0", ">= 0 and < 0.5"

  static constexpr Range any() { return {}; }
  static constexpr Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  // (0, hi]
  static constexpr Range positive(double hi = std::numeric_limits<double>::infinity()) {
    return {0.0, hi, true, false};
  }
  // [0, hi]
  static constexpr Range non_negative(double hi = std::numeric_limits<double>::infinity()) {
    return {0.0, hi, false, false};
  }
};

enum class Type {
  Number,   // a float or an integer
  Integer,  // an integer only
  Boolean,
  String,    // free text
  Choice,    // one of `choices`
  Vector,    // [x, y] in 2D, [x, y, z] in 3D; `range` bounds each component
  Points,    // an array of [x, y] pairs (polygon vertices)
  Table,     // a sub-table, itself a section
  Tables,    // an array of tables ([[name]]), each a section
  K0,        // initial_stress.k0: a number or a rule name
  Side,      // a boundary side: a string or an inline table (boundary.side)
  Profile,   // a profile y(x): a CSV file name or inline [[x, y], ...] with x increasing
  BodyPair,  // [name, name] of two [[body]] tables, or "all"
  Fields,    // "default", "all" or a list of `choices` (which may hold "default")
};
const char* to_string(Type t);

enum class DefaultKind {
  Required,  // no default: the key must be given
  None,      // absent means "off" / "not used"
  Value,     // `value`
  Derived,   // computed from other keys, described in `text`
};

struct Default {
  DefaultKind kind = DefaultKind::Required;
  double value = 0.0;
  const char* text = "";
};
constexpr Default required() { return {}; }
constexpr Default none(const char* text = "") { return {DefaultKind::None, 0.0, text}; }
constexpr Default value(double v) { return {DefaultKind::Value, v, ""}; }
// A default stated as text (a string default, a vector, or one computed from other keys).
constexpr Default derived(const char* text) { return {DefaultKind::Derived, 0.0, text}; }

struct Key {
  const char* name;
  Type type = Type::Number;
  const char* unit = "";  // SI unit, "-" when dimensionless, "" for non-numbers
  Default def = required();
  Range range = Range::any();
  const char* choices = "";  // Choice (and K0 rules): allowed spellings separated by '|'
  const char* doc = "";      // meaning, with the seed equation where there is one
};

// One table of the scenario file, e.g. "grid", "material", "body (rectangle)".
struct Section {
  std::string name;   // as in key paths and headings: "grid", "stage.material", ...
  std::string title;  // the markdown block's name in docs/scenario.md
  std::vector<Key> keys;

  const Key* find(std::string_view key) const;
  // The key; throws std::logic_error if the section does not declare it (a parser bug).
  const Key& at(std::string_view key) const;
};

// Every section, in the order docs/scenario.md presents them.
const std::vector<Section>& sections();
// The section called `name` (e.g. "solver", "material (mohr-coulomb)"); throws
// std::logic_error if there is none.
const Section& section(std::string_view name);

// The allowed spellings of a Choice key.
std::vector<std::string> choices_of(const Key& k);

// The markdown key table of a section, as docs/scenario.md holds it.
std::string markdown_table(const Section& s);
// `doc` with every generated block (between "<!-- schema: NAME -->" and
// "<!-- /schema -->") replaced by the current table of section NAME. Throws
// std::runtime_error naming an unknown section or an unterminated block.
std::string update_generated_blocks(const std::string& doc);

}  // namespace skred::schema
