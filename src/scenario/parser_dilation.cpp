// The dilated continua of a run with contact (Paper III §C.3.2): "all material points that
// has obtained the maximum void ratio" form a new continuum, which slides on the remaining
// sand. A deformable body whose Mohr-Coulomb material has the dilation cut-off gets one more
// body, "<name>_dilated", without points; the run moves the points that reach the cut-off
// into it (run/dilation_continuum.hpp). docs/method.md, "Dilation cut-off as a new continuum".
#include <algorithm>
#include <cmath>
#include <utility>

#include "scenario/parser_detail.hpp"
#include "solver/contact.hpp"

namespace skred::scenario_detail {

namespace {

bool has_cutoff(const Material& m) {
  return m.model == Model::MohrCoulomb && m.mohr_coulomb.max_void_ratio > 0.0;
}

}  // namespace

template <int D>
void add_dilation_continua(const TableReader& root, ScenarioOf<D>& s) {
  const auto tables = root.array_of_tables("body");
  const int n = static_cast<int>(s.bodies.size());
  const bool contact = !s.contacts.empty();
  std::vector<int> dilated(static_cast<std::size_t>(n), -1);  // per body: its dilated continuum
  for (int i = 0; i < n && i < static_cast<int>(tables.size()); ++i) {
    const TableReader& t = tables[static_cast<std::size_t>(i)];
    const BodyOf<D>& b = s.bodies[static_cast<std::size_t>(i)];
    const Material& m = s.materials[static_cast<std::size_t>(b.material)];
    // By default with contact only: without it a run keeps one velocity field (psi = 0 only).
    const bool possible = !b.rigid && has_cutoff(m);
    const bool wanted = t.boolean_or("dilation_continuum", contact && possible);
    if (wanted && b.rigid) t.fail_at("dilation_continuum", "a rigid body has no dilation cut-off");
    if (wanted && !possible)
      t.fail_at("dilation_continuum",
                fmt::format("material \"{}\" has no dilation cut-off: a mohr-coulomb material with "
                            "initial_void_ratio and max_void_ratio is needed",
                            m.name));
    if (!wanted) continue;
    BodyOf<D> d = b;
    d.name = b.name + "_dilated";
    d.dilated_from = i;
    for (const BodyOf<D>& o : s.bodies)
      if (o.name == d.name)
        t.fail_at("dilation_continuum",
                  fmt::format("the dilated continuum of body \"{}\" is called \"{}\", the name of another "
                              "body; rename that body or set dilation_continuum = false",
                              b.name, d.name));
    if (s.bodies.size() >= static_cast<std::size_t>(kMaxContactBodies))
      t.fail_at("dilation_continuum",
                fmt::format("with the dilated continua the run would have more than {} bodies, the most "
                            "contact supports; set dilation_continuum = false on some bodies",
                            kMaxContactBodies));
    dilated[static_cast<std::size_t>(i)] = static_cast<int>(s.bodies.size());
    if (!s.splitting.body_splits.empty()) s.splitting.body_splits.push_back(d.split ? 1 : 0);
    s.bodies.push_back(std::move(d));  // (b is not used after this)
  }
  // The dilated sand slides on its parent with the parent's friction, mu = tan(phi) (Paper
  // III §C.3.2); with every other body it keeps its parent's contact (bonded where that is).
  const std::vector<ContactPair> file = s.contacts;
  auto family = [&](int b) {
    std::vector<int> f{b};
    if (dilated[static_cast<std::size_t>(b)] >= 0) f.push_back(dilated[static_cast<std::size_t>(b)]);
    return f;
  };
  for (const ContactPair& c : file)
    for (int a : family(c.a))
      for (int b : family(c.b))
        if (a != c.a || b != c.b)
          s.contacts.push_back({std::min(a, b), std::max(a, b), c.friction, c.detection});
  for (int i = 0; i < n; ++i)
    if (const int d = dilated[static_cast<std::size_t>(i)]; d >= 0) {
      const Material& m =
          s.materials[static_cast<std::size_t>(s.bodies[static_cast<std::size_t>(i)].material)];
      s.contacts.push_back({i, d, std::tan(m.mohr_coulomb.friction)});
    }
}

template void add_dilation_continua<2>(const TableReader&, Scenario&);
template void add_dilation_continua<3>(const TableReader&, Scenario3&);

}  // namespace skred::scenario_detail
