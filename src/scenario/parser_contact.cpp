// The [[contact]] tables of a scenario file: frictional contact between named bodies (Paper
// III §C.2.7). docs/scenario.md, "Contact between bodies", documents them.
#include <set>
#include <utility>

#include "scenario/parser_detail.hpp"
#include "solver/contact.hpp"

namespace skred::scenario_detail {

namespace {

// Index of the body called `name`, or a message listing the bodies.
template <int D>
int body_index(const TableReader& t, const ScenarioOf<D>& s, const std::string& name) {
  std::string names;
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    if (s.bodies[i].name == name) return static_cast<int>(i);
    names += fmt::format("{}\"{}\"", i ? ", " : "", s.bodies[i].name);
  }
  t.fail_at("bodies", fmt::format("no body is called \"{}\"; the bodies are {}", name, names));
}

}  // namespace

template <int D>
void parse_contacts(const TableReader& root, ScenarioOf<D>& s) {
  const auto tables = root.array_of_tables("contact");
  if (tables.empty()) return;
  if (s.bodies.size() > static_cast<std::size_t>(kMaxContactBodies))
    fail(s.source, root.where("contact"), "contact",
         fmt::format("contact supports at most {} bodies, the scenario has {}", kMaxContactBodies,
                     s.bodies.size()));
  for (std::size_t i = 0; i < s.bodies.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (s.bodies[i].name == s.bodies[j].name)
        fail(s.source, root.where("contact"), "contact",
             fmt::format("bodies {} and {} are both called \"{}\"; contact needs distinct body names", j, i,
                         s.bodies[i].name));
  static constexpr Choices<ContactDetection> kDetection = {{"fill", ContactDetection::Fill},
                                                           {"traction", ContactDetection::Traction}};
  std::set<std::pair<int, int>> seen;
  for (const TableReader& t : tables) {
    t.allow_declared();
    const double mu = t.number("friction");
    const ContactDetection detection =
        t.choice<ContactDetection>("detection", kDetection, ContactDetection::Fill);
    std::vector<std::pair<int, int>> pairs;
    if (!t.has("bodies")) t.fail_missing("bodies");
    if (t.find("bodies")->is_string()) {
      if (t.string("bodies") != "all")
        t.fail_at("bodies", "write two body names, [\"clay\", \"sand\"], or \"all\"");
      for (int a = 0; a < static_cast<int>(s.bodies.size()); ++a)
        for (int b = a + 1; b < static_cast<int>(s.bodies.size()); ++b) pairs.emplace_back(a, b);
    } else {
      const auto* arr = t.find("bodies")->as_array();
      if (!arr || arr->size() != 2 || !arr->get(0)->is_string() || !arr->get(1)->is_string())
        t.fail_type("bodies", "two body names, [\"clay\", \"sand\"], or \"all\"");
      const int a = body_index(t, s, *arr->get(0)->value<std::string>());
      const int b = body_index(t, s, *arr->get(1)->value<std::string>());
      if (a == b)
        t.fail_at("bodies",
                  fmt::format("a body cannot be in contact with itself (\"{}\")", s.bodies[a].name));
      pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
    for (const auto& [a, b] : pairs) {
      if (!seen.insert({a, b}).second)
        t.fail_at("bodies", fmt::format("the pair \"{}\" - \"{}\" has a contact already", s.bodies[a].name,
                                        s.bodies[b].name));
      s.contacts.push_back({a, b, mu, detection});
    }
  }
}

template void parse_contacts<2>(const TableReader&, Scenario&);
template void parse_contacts<3>(const TableReader&, Scenario3&);

}  // namespace skred::scenario_detail
