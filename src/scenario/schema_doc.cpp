// docs/scenario.md's key tables, generated from the schema (schema.hpp).
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include "scenario/schema.hpp"

namespace skred::schema {

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  const std::string l = fmt::format("{} {:g}", lo_open ? ">" : ">=", lo);
  const std::string h = fmt::format("{} {:g}", hi_open ? "<" : "<=", hi);
  if (has_lo && has_hi) return l + " and " + h;
  if (has_lo) return l;
  if (has_hi) return h;
  return "finite";
}

namespace {

std::string quoted_choices(const Key& k) {
  std::string t;
  for (const auto& c : choices_of(k)) t += fmt::format("{}`\"{}\"`", t.empty() ? "" : ", ", c);
  return t;
}

// A '|'-separated list as `a`, `b`, ...
std::string code_list(const char* list) {
  std::string t;
  for (std::string_view rest = list; !rest.empty();) {
    const std::size_t bar = std::min(rest.find('|'), rest.size());
    t += fmt::format("{}`{}`", t.empty() ? "" : ", ", rest.substr(0, bar));
    rest.remove_prefix(std::min(bar + 1, rest.size()));
  }
  return t;
}

std::string default_text(const Key& k) {
  if (k.type == Type::Fields) return code_list(k.def.text);
  switch (k.def.kind) {
    case DefaultKind::Required: return "required";
    case DefaultKind::None: return *k.def.text ? k.def.text : "none";
    case DefaultKind::Value: return fmt::format("`{}`", k.def.value);
    case DefaultKind::Derived: {
      const std::string t = k.def.text;  // a literal in code font, a description as it is
      const bool literal = t[0] == '"' || t[0] == '[' || std::isdigit(static_cast<unsigned char>(t[0])) ||
                           t == "true" || t == "false";
      return literal && t.find(' ') == std::string::npos ? "`" + t + "`" : t;
    }
  }
  return "";
}

std::string allowed_text(const Key& k) {
  switch (k.type) {
    case Type::Number: return k.range.describe();
    case Type::Integer: return fmt::format("{} to {}", k.range.lo, k.range.hi);
    case Type::Vector:
    case Type::Points: return "each component " + k.range.describe();
    case Type::Choice: return quoted_choices(k);
    case Type::K0: return quoted_choices(k) + " or a number " + k.range.describe();
    case Type::Boolean: return "`true`, `false`";
    case Type::Side: return "see below";
    case Type::Profile: return "x strictly increasing; inside the grid; 3D: covers the grid";
    case Type::BodyPair: return "two different body names, or `\"all\"`";
    case Type::Fields: return "`\"default\"`, `\"all\"`, or a list of " + code_list(k.choices);
    case Type::String:
    case Type::Table:
    case Type::Tables: break;
  }
  return "";
}

}  // namespace

std::string markdown_table(const Section& s) {
  std::string t =
      "| key | type | unit | default | allowed | meaning |\n"
      "|-----|------|------|---------|---------|---------|\n";
  for (const Key& k : s.keys) {
    const std::string unit = *k.unit ? k.unit : "–";
    t += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", k.name, to_string(k.type), unit, default_text(k),
                     allowed_text(k), k.doc);
  }
  return t;
}

std::string update_generated_blocks(const std::string& doc) {
  static const std::string open = "<!-- schema: ", close = "<!-- /schema -->";
  std::string out;
  std::size_t pos = 0;
  while (true) {
    const std::size_t a = doc.find(open, pos);
    if (a == std::string::npos) break;
    const std::size_t name_end = doc.find(" -->", a);
    if (name_end == std::string::npos) throw std::runtime_error("unterminated '<!-- schema:' marker");
    const std::string title = doc.substr(a + open.size(), name_end - a - open.size());
    const std::size_t body = doc.find('\n', name_end);
    const std::size_t b = doc.find(close, name_end);
    if (body == std::string::npos || b == std::string::npos)
      throw std::runtime_error("block '" + title + "' has no '" + close + "'");
    const Section* found = nullptr;
    for (const Section& s : sections())
      if (s.title == title) found = &s;
    if (!found) throw std::runtime_error("no schema section is called '" + title + "'");
    out += doc.substr(pos, body + 1 - pos);
    out += markdown_table(*found);
    out += close;
    pos = b + close.size();
  }
  out += doc.substr(pos);
  return out;
}

}  // namespace skred::schema
