// The implicit integrator's part of a scenario file (González Acosta et al. 2020):
// solver.integrator and the stages' `integrator`, [implicit] with each stage's
// [stage.implicit] over it, the [[pressure]] and [[prescribed_velocity]] tables, and what an
// integrator refuses
// (docs/scenario.md, "The implicit integrator").
#include <optional>
#include <string>

#include "parallel/processes.hpp"
#include "scenario/initial_stress.hpp"
#include "scenario/parser_detail.hpp"

namespace skred::scenario_detail {

namespace {

constexpr Choices<IntegratorKind> kIntegrators = {{"explicit", IntegratorKind::Explicit},
                                                  {"implicit", IntegratorKind::Implicit}};

constexpr const char* kSideNames[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};

// Index of the body of the file called `name` (not a dilated continuum), or a message listing them.
template <int D>
int pressure_body(const TableReader& t, const ScenarioOf<D>& s) {
  const std::string name = t.string("body");
  std::string names;
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    if (s.bodies[i].dilated_from >= 0) continue;
    if (s.bodies[i].name == name) return static_cast<int>(i);
    names += fmt::format("{}\"{}\"", names.empty() ? "" : ", ", s.bodies[i].name);
  }
  t.fail_at("body", fmt::format("no [[body]] is called \"{}\"; the bodies are {}", name, names));
}

// Refuses the tables `key` ("<what> applied by the implicit integrator only") when a stage,
// `explicit_stage`, runs the explicit integrator.
void implicit_only(const TableReader& root, const ScenarioCommon& s, const char* key, const char* what,
                   const Stage* explicit_stage) {
  if (!explicit_stage) return;
  fail(s.source, root.where(key), key,
       fmt::format("{} applied by the implicit integrator only, and stage \"{}\" runs the explicit one; set "
                   "integrator = \"implicit\" for every stage",
                   what, explicit_stage->name));
}

// The [[pressure]] tables; `explicit_stage` is a stage that runs the explicit integrator, if any.
template <int D>
void parse_pressures(const TableReader& root, ScenarioOf<D>& s, const Stage* explicit_stage) {
  const auto tables = root.array_of_tables("pressure");
  if (tables.empty()) return;
  implicit_only(root, s, "pressure", "pressures are", explicit_stage);
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const TableReader& t = tables[i];
    t.allow_declared();
    BoundaryPressure p;
    p.body = pressure_body(t, s);
    p.side = t.choice<int>(
        "side", {{"x_min", 0}, {"x_max", 1}, {"y_min", 2}, {"y_max", 3}, {"z_min", 4}, {"z_max", 5}});
    if (p.side >= 2 * D) t.fail_at("side", fmt::format("\"{}\" needs a 3D grid", t.string("side")));
    p.pressure = t.number("value");
    p.ramp_time = t.number("ramp_time");
    for (std::size_t j = 0; j < s.pressures.size(); ++j)
      if (s.pressures[j].body == p.body && s.pressures[j].side == p.side)
        t.fail_at("side",
                  fmt::format("body \"{}\" has a pressure on its {} face already (pressure[{}])",
                              s.bodies[static_cast<std::size_t>(p.body)].name, kSideNames[p.side], j));
    s.pressures.push_back(p);
  }
}

// The [[prescribed_velocity]] tables: a box that holds at least one grid node inside the grid.
template <int D>
void parse_prescribed(const TableReader& root, ScenarioOf<D>& s, const Stage* explicit_stage) {
  const auto tables = root.array_of_tables("prescribed_velocity");
  if (tables.empty()) return;
  implicit_only(root, s, "prescribed_velocity", "prescribed velocities are", explicit_stage);
  if (s.interpolation == Interpolation::Bspline)
    fail(s.source, root.where("prescribed_velocity"), "prescribed_velocity",
         "the cubic B-spline's degrees of freedom are control points, not the displacements of the nodes: "
         "prescribed velocities need interpolation = \"linear\", \"gimp\" or \"gimp-quadrature\"");
  if (tables.size() > static_cast<std::size_t>(kMaxPrescribed))
    tables[kMaxPrescribed].fail_at("name",
                                   fmt::format("at most {} [[prescribed_velocity]] tables", kMaxPrescribed));
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const TableReader& t = tables[i];
    t.allow_declared();
    PrescribedVelocity pv;
    pv.name = t.has("name") ? t.string("name") : fmt::format("prescribed{}", i);
    for (const PrescribedVelocity& other : s.prescribed)
      if (other.name == pv.name)
        t.fail_at("name", fmt::format("another [[prescribed_velocity]] is called \"{}\"", pv.name));
    if (pv.name.empty() || pv.name.find_first_of(" ,\"\n\t") != std::string::npos)
      t.fail_at("name", "a name without spaces, commas or quotes (it names series.csv's columns)");
    const Vec<D> lo = t.vec<D>("min"), hi = t.vec<D>("max"), v = t.vec<D>("velocity");
    const char* axes = "xyz";
    int held = 0;
    if (t.has("components")) {
      const std::string c = t.string("components");
      if (c == "all") {
        held = (1 << D) - 1;
      } else if (c.size() == 1 && c[0] >= 'x' && c[0] < 'x' + D) {
        held = 1 << (c[0] - 'x');
      } else {
        t.fail_at("components", fmt::format("\"{}\": one of \"all\", {}", c,
                                            D == 3 ? "\"x\", \"y\", \"z\"" : "\"x\", \"y\""));
      }
    } else {
      held = (1 << D) - 1;
    }
    pv.components = static_cast<std::uint8_t>(held);
    // The nodes in the box: at least one per axis, inside the grid.
    for (int d = 0; d < D; ++d) {
      if (!(hi[d] >= lo[d]))
        t.fail_at("max", fmt::format("max[{}] = {} is below min[{}] = {}", d, hi[d], d, lo[d]));
      const double tol = 1e-9 * s.cell_size;
      const double first = std::ceil((lo[d] - s.origin[d] - tol) / s.cell_size);
      const double last = std::floor((hi[d] - s.origin[d] + tol) / s.cell_size);
      if (first > last || last < 0.0 || first > s.cells[d])
        t.fail_at("min",
                  fmt::format("the box [{}, {}] along {} holds no grid node inside the grid (nodes every "
                              "{} m from {})",
                              lo[d], hi[d], axes[d], s.cell_size, s.origin[d]));
      pv.min[static_cast<std::size_t>(d)] = lo[d];
      pv.max[static_cast<std::size_t>(d)] = hi[d];
      pv.velocity[static_cast<std::size_t>(d)] = v[d];
    }
    s.prescribed.push_back(pv);
  }
}

const char* analysis_text(ImplicitAnalysis a) {
  return a == ImplicitAnalysis::Dynamic
             ? "only a dynamic analysis (analysis = \"dynamic\") has a time step; "
               "a quasi-static one is split into load_steps"
             : "only a quasi-static analysis (analysis = \"quasi-static\") is split "
               "into load steps; a dynamic one takes time_step";
}

}  // namespace

void parse_implicit_settings(const TableReader& t, ImplicitSettings& im) {
  t.allow_declared();
  if (t.has("analysis"))
    im.analysis = t.choice<ImplicitAnalysis>("analysis", {{"quasi-static", ImplicitAnalysis::QuasiStatic},
                                                          {"dynamic", ImplicitAnalysis::Dynamic}});
  if (t.has("time_step")) im.time_step = t.number("time_step");
  if (t.has("load_steps")) im.load_steps = static_cast<int>(t.integer("load_steps"));
  if (t.has("iteration"))
    im.iteration = t.choice<ImplicitIteration>("iteration", {{"newton", ImplicitIteration::Newton},
                                                             {"elastic", ImplicitIteration::Elastic},
                                                             {"single", ImplicitIteration::Single}});
  if (t.has("residual_tolerance")) im.residual_tolerance = t.number("residual_tolerance");
  if (t.has("displacement_tolerance")) im.displacement_tolerance = t.number("displacement_tolerance");
  if (t.has("max_iterations")) im.max_iterations = static_cast<int>(t.integer("max_iterations"));
  if (t.has("line_search")) im.line_search = t.boolean_or("line_search", im.line_search);
  if (t.has("max_cuts")) im.max_cuts = static_cast<int>(t.integer("max_cuts"));
  if (t.has("min_node_fill")) im.min_node_fill = t.number("min_node_fill");
  if (t.has("linear_solver"))
    im.linear_solver = t.choice<LinearSolverKind>(
        "linear_solver", {{"direct", LinearSolverKind::Direct}, {"iterative", LinearSolverKind::Iterative}});
  if (t.has("petsc_options")) im.petsc_options = t.string("petsc_options");
  if (t.has("integration"))
    im.integration = t.choice<ForceIntegration>(
        "integration", {{"points", ForceIntegration::Points},
                        {"modified-weights", ForceIntegration::ModifiedWeights},
                        {"gauss-mapping", ForceIntegration::GaussMapping},
                        {"double-mapping", ForceIntegration::DoubleMapping},
                        {"double-mapping-gimp", ForceIntegration::DoubleMappingGimp}});
  if (t.has("stress_recovery"))
    im.stress_recovery = t.choice<StressRecovery>(
        "stress_recovery", {{"points", StressRecovery::Points}, {"cmpm", StressRecovery::Cmpm}});
}

void parse_integrator(const TableReader& root, const TableReader& solver, ScenarioCommon& s) {
  s.integrator = solver.choice<IntegratorKind>("integrator", kIntegrators, IntegratorKind::Explicit);
  if (const auto t = root.table("implicit", false)) parse_implicit_settings(*t, s.implicit);
}

// Axisymmetric geometry (either integrator): the axis r = 0, where the grid starts there, is a
// symmetry line (a roller: boundary.x_min is "roller" or left out); what neither integrator
// models in it is refused, naming the key.
template <int D>
void check_axisymmetric(const TableReader& root, ScenarioOf<D>& s) {
  const auto why = [](const std::string& what) {
    return fmt::format("{} is not available in axisymmetric geometry (grid.geometry)", what);
  };
  if (s.origin[0] == 0.0) {
    BoundarySide& axis = s.boundaries[0];
    if (axis.kind != BoundaryKind::Free && axis.kind != BoundaryKind::Roller)
      root.table("boundary", true)
          ->fail_at("x_min",
                    "in axisymmetric geometry the grid's x_min side is the axis r = 0, a symmetry line: "
                    "set it to \"roller\" or leave it out");
    axis.kind = BoundaryKind::Roller;
  }
  if (root.has("contact")) fail(s.source, root.where("contact"), "contact", why("contact between bodies"));
  const std::vector<TableReader> body_tables = root.array_of_tables("body");
  for (std::size_t i = 0; i < body_tables.size() && i < s.bodies.size(); ++i) {
    if (s.bodies[i].rigid) body_tables[i].fail_at("rigid", why("a rigid body"));
    if (s.bodies[i].split)  // a split point's halves lie at other radii, whose masses per radian differ
      body_tables[i].fail_at("split", why("material-point splitting"));
  }
  for (const BodyOf<D>& b : s.bodies)
    if (b.dilated_from >= 0 && static_cast<std::size_t>(b.dilated_from) < body_tables.size())
      body_tables[static_cast<std::size_t>(b.dilated_from)].fail_at("dilation_continuum",
                                                                    why("a dilated continuum"));
  if (s.centre_shear)
    root.table("solver", true)->fail_at("shear_strain", why("shear_strain = \"cell-centre\""));
}

template <int D>
void check_remedies(const TableReader& root, ScenarioOf<D>& s);

template <int D>
void check_integrators(const TableReader& root, ScenarioOf<D>& s) {
  const std::vector<TableReader> stage_tables = root.array_of_tables("stage");  // none: one stage
  const auto stage_implicit = [&](std::size_t k) -> std::optional<TableReader> {
    if (k >= stage_tables.size()) return std::nullopt;
    const auto t = stage_tables[k].table("implicit", false);
    if (!t) return std::nullopt;
    return t->follows("implicit");
  };
  const Stage* explicit_stage = nullptr;
  const Stage* implicit_stage = nullptr;
  for (const Stage& st : s.stages) {
    const Stage*& first = st.integrator == IntegratorKind::Implicit ? implicit_stage : explicit_stage;
    if (!first) first = &st;
  }
  const std::optional<TableReader> implicit = root.table("implicit", false);
  if (implicit && !implicit_stage)
    fail(s.source, root.where("implicit"), "implicit",
         "no stage runs the implicit integrator; set solver.integrator = \"implicit\" (or a stage's "
         "integrator = \"implicit\"), or remove [implicit]");
  for (std::size_t k = 0; k < stage_tables.size() && k < s.stages.size(); ++k)
    if (s.stages[k].integrator == IntegratorKind::Explicit && stage_tables[k].has("implicit"))
      stage_tables[k].fail_at("implicit", fmt::format("the stage (\"{}\") runs the explicit integrator; set "
                                                      "integrator = \"implicit\"",
                                                      s.stages[k].name));
  if (s.geometry == Geometry::Axisymmetric) check_axisymmetric(root, s);
  parse_pressures(root, s, explicit_stage);
  parse_prescribed(root, s, explicit_stage);
  if (!implicit_stage) return;
  if (!built_with_mpi()) {  // (CMake's SKRED_MPI=OFF: no PETSc, whose solvers the integrator uses)
    const std::size_t k = static_cast<std::size_t>(implicit_stage - s.stages.data());
    const std::string why =
        "the implicit integrator solves with PETSc, and this build of skred has none (configured "
        "with cmake -DSKRED_MPI=OFF, without MPI and PETSc); rebuild with the default "
        "(-DSKRED_MPI=ON, README) or use integrator = \"explicit\"";
    if (k < stage_tables.size() && stage_tables[k].has("integrator"))
      stage_tables[k].fail_at("integrator", why);
    root.table("solver", true)->fail_at("integrator", why);
  }
  check_remedies(root, s);

  // What the implicit integrator does not support (yet).
  const auto why = [&](const std::string& what) {
    return fmt::format("{} is not available with integrator = \"implicit\" (stage \"{}\")", what,
                       implicit_stage->name);
  };
  if (root.has("contact"))
    fail(s.source, root.where("contact"), "contact", why("contact between bodies ([[contact]])"));
  const std::vector<TableReader> body_tables = root.array_of_tables("body");
  for (std::size_t i = 0; i < body_tables.size() && i < s.bodies.size(); ++i) {
    if (s.bodies[i].rigid)
      body_tables[i].fail_at("rigid", why(fmt::format("a rigid body (\"{}\")", s.bodies[i].name)));
    if (s.bodies[i].split) body_tables[i].fail_at("split", why("material-point splitting"));
  }
  for (const BodyOf<D>& b : s.bodies)
    if (b.dilated_from >= 0 && static_cast<std::size_t>(b.dilated_from) < body_tables.size())
      body_tables[static_cast<std::size_t>(b.dilated_from)].fail_at(
          "dilation_continuum", why(fmt::format("a dilated continuum (\"{}\")", b.name)));
  if (!s.contacts.empty()) fail(s.source, root.where("body"), "body", why("contact between bodies"));
  for (int k = 0; k < 2 * D; ++k)
    if (s.boundaries[static_cast<std::size_t>(k)].kind == BoundaryKind::Friction)
      root.table("boundary", true)->fail_at(kSideNames[k], why("a frictional wall (type = \"friction\")"));
  for (std::size_t k = 0; k < stage_tables.size() && k < s.stages.size(); ++k)
    if (s.stages[k].integrator == IntegratorKind::Implicit && s.stages[k].local_damping > 0.0)
      stage_tables[k].fail_at("local_damping",
                              fmt::format("local damping is not available with integrator = \"implicit\" "
                                          "(stage \"{}\")",
                                          s.stages[k].name));

  // time_step is read by dynamic stages only, load_steps by quasi-static ones.
  const std::pair<const char*, ImplicitAnalysis> uses[2] = {{"time_step", ImplicitAnalysis::Dynamic},
                                                            {"load_steps", ImplicitAnalysis::QuasiStatic}};
  for (const auto& [key, analysis] : uses) {
    bool read = false;  // an implicit stage of that analysis takes [implicit]'s value
    for (std::size_t k = 0; k < s.stages.size(); ++k) {
      const Stage& st = s.stages[k];
      if (st.integrator != IntegratorKind::Implicit) continue;
      const auto own = stage_implicit(k);
      if (own && own->has(key)) {
        if (st.implicit.analysis != analysis)
          own->fail_at(key, fmt::format("stage \"{}\" is {}: {}", st.name, to_string(st.implicit.analysis),
                                        analysis_text(analysis)));
      } else if (st.implicit.analysis == analysis) {
        read = true;
      }
    }
    if (implicit && implicit->has(key) && !read)
      implicit->fail_at(key, fmt::format("no {} implicit stage reads it: {}", to_string(analysis),
                                         analysis_text(analysis)));
  }
}

// Acosta's remedies where the paper defines them (§5.2-5.5): W*, GM and DM over the linear
// shape functions, DM-G over GIMP's support domains, CMPM beside either; neither with the
// cell-averaged volumetric strain. The error names the table that chose it.
template <int D>
void check_remedies(const TableReader& root, ScenarioOf<D>& s) {
  const std::vector<TableReader> stage_tables = root.array_of_tables("stage");
  for (std::size_t k = 0; k < s.stages.size(); ++k) {
    const Stage& st = s.stages[k];
    if (st.integrator != IntegratorKind::Implicit) continue;
    const auto where = [&](const char* key) -> TableReader {
      if (k < stage_tables.size())
        if (const auto t = stage_tables[k].table("implicit", false); t && t->has(key)) return *t;
      return *root.table("implicit", true);
    };
    const ForceIntegration f = st.implicit.integration;
    // The mapped integrations of an elastic stage take Acosta's load stepping unless the
    // scenario chooses an iteration: iterated to equilibrium, the mapped force admits
    // oscillating point stresses (R6 by §3.1: 32 % against 7.6 %). A stage whose materials
    // yield keeps Newton: the load stepping, its out-of-balance force never removed, loses a
    // third of the vertical cut's gravity work (docs/studies/2026-12-03-vertical-cut-slivers.md).
    const bool mapped_force = f == ForceIntegration::GaussMapping || f == ForceIntegration::DoubleMapping ||
                              f == ForceIntegration::DoubleMappingGimp;
    const bool stage_sets = k < stage_tables.size() && stage_tables[k].table("implicit", false) &&
                            stage_tables[k].table("implicit", false)->has("iteration");
    const auto top = root.table("implicit", false);
    bool yields = false;
    for (const Material& m : stage_materials(s, st)) yields = yields || m.plastic();
    if (mapped_force && !yields && !stage_sets && !(top && top->has("iteration")))
      s.stages[k].implicit.iteration = ImplicitIteration::Single;
    const bool linear_only = f == ForceIntegration::ModifiedWeights || f == ForceIntegration::GaussMapping ||
                             f == ForceIntegration::DoubleMapping;
    if (linear_only && s.interpolation != Interpolation::Linear)
      where("integration")
          .fail_at("integration", fmt::format("integration = \"{}\" maps over the linear shape functions "
                                              "(Acosta §5.2-5.3): set solver.interpolation = \"linear\" (it "
                                              "is \"{}\"), or take \"double-mapping-gimp\" with \"gimp\"",
                                              to_string(f), to_string(s.interpolation)));
    if (f == ForceIntegration::DoubleMappingGimp && s.interpolation != Interpolation::Gimp)
      where("integration")
          .fail_at("integration", fmt::format("integration = \"double-mapping-gimp\" maps over GIMP's "
                                              "support domains (Acosta §5.4): set solver.interpolation = "
                                              "\"gimp\" (it is \"{}\")",
                                              to_string(s.interpolation)));
    if (st.implicit.stress_recovery == StressRecovery::Cmpm && s.interpolation != Interpolation::Linear &&
        s.interpolation != Interpolation::Gimp)
      where("stress_recovery")
          .fail_at("stress_recovery",
                   fmt::format("stress_recovery = \"cmpm\" (Acosta §5.5) is defined with the "
                               "\"linear\" and \"gimp\" interpolations, not \"{}\"",
                               to_string(s.interpolation)));
    if (!st.implicit.at_points() && s.volumetric_averaging && s.volumetric_by_default) {
      s.volumetric_averaging = false;  // "auto": the remedies integrate at the points' strains
    } else if (!st.implicit.at_points() && s.volumetric_averaging) {
      const char* key = f != ForceIntegration::Points ? "integration" : "stress_recovery";
      where(key).fail_at(key,
                         "Acosta's remedies are not available with the cell-averaged volumetric strain "
                         "(solver.volumetric_strain = \"cell-average\")");
    }
  }
}

template void check_remedies<2>(const TableReader&, Scenario&);
template void check_remedies<3>(const TableReader&, Scenario3&);
template void check_integrators<2>(const TableReader&, Scenario&);
template void check_integrators<3>(const TableReader&, Scenario3&);

}  // namespace skred::scenario_detail
