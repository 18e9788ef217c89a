// Parameter sweeps: a value replaced in the parsed TOML document before validation.
#include <cmath>
#include <cstdlib>

#include "scenario/parser_detail.hpp"

namespace skred::scenario_detail {

namespace {

// Walks a key path such as "material[0].friction" or "material[sand].friction" (an array
// element chosen by its name key) or "stage[1].material[0].cohesion" and hands the table that
// holds its last component, and that component, to `assign`. With `create`, a missing table
// on the way (not an array element) is added, e.g. [solver] for "solver.velocity_transfer".
template <class Assign>
void at_key(toml::table& doc, const std::string& path, const std::string& source, bool create,
            Assign&& assign) {
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
      assign(*table, part);
      return;
    }
    toml::node* next = table->get(part);
    if (!next && create && index.empty())
      next = table->insert_or_assign(part, toml::table{}).first->second.as_table();
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

}  // namespace

void set_key(toml::table& doc, const std::string& path, double value, const std::string& source) {
  at_key(doc, path, source, false, [&](toml::table& table, const std::string& key) {
    const toml::node* old = table.get(key);
    if (old && old->is_integer() && value == std::floor(value))
      table.insert_or_assign(key, static_cast<std::int64_t>(value));
    else
      table.insert_or_assign(key, value);
  });
}

void set_key(toml::table& doc, const std::string& path, const std::string& value, const std::string& source) {
  at_key(doc, path, source, true,
         [&](toml::table& table, const std::string& key) { table.insert_or_assign(key, value); });
  // A transfer set from outside comes with its own defaults: the keys of another transfer
  // (parse_transfer.cpp) would refuse it, and those of the same one would not be what was asked.
  if (path == "solver.velocity_transfer")
    if (toml::table* solver = doc["solver"].as_table())
      for (const char* key : {"pic_fraction", "xpic_order", "xpic_period"}) solver->erase(key);
}

}  // namespace skred::scenario_detail
