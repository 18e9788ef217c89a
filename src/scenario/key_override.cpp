// Parameter sweeps: a value replaced in the parsed TOML document before validation.
#include <cmath>
#include <cstdlib>

#include "scenario/parser_detail.hpp"

namespace skred::scenario_detail {

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

}  // namespace skred::scenario_detail
